// Surfaces seen from behind: a box meant to be seen from outside but turned inside out is
// named, with the share of the image it fills; the same box the right way round is not.
#include "solver/render/back_faces.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "solver/scene/mesh.h"

namespace bumprad {
namespace {

Scene box_scene(bool flip) {
  Scene s;
  s.materials.push_back(Material{});
  Object box;
  box.name = "crate";
  box.shape = BoxShape{Vec3(0), Vec3(1), Vec3(0)};
  box.flip_normals = flip;
  s.objects.push_back(box);
  s.camera.position = Vec3(0, 0, 2);
  s.camera.look_at = Vec3(0);
  s.camera.width = s.camera.height = 100;
  s.camera.fov_y_deg = 40;
  return s;
}

TEST(BackFaces, AnObjectSeenFromBehindIsNamedWithItsShare) {
  const Scene inside_out = box_scene(true);
  const Mesh mesh = build_mesh(inside_out);
  const RayScene rays(mesh);
  const auto found = back_facing_objects(inside_out, mesh, rays);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].object, 0u);
  // The near face (z = 0.5, 1.5 away), turned in, fills a square of side
  // 1 / (2 * 1.5 * tan 20 deg) of the image, 84 % of it: the grid of 64 x 64 rays finds that
  // to within a row and a column.
  const double side = 1 / (2 * 1.5 * std::tan(20 * std::numbers::pi / 180));
  EXPECT_NEAR(found[0].share, side * side, 2.0 / 64);
  const auto warnings = back_face_warnings(inside_out, mesh, rays);
  ASSERT_EQ(warnings.size(), 1u);
  const std::string percent = std::to_string(int(std::lround(100 * found[0].share)));
  EXPECT_EQ(
      warnings[0].rfind("object \"crate\": " + percent + " % of the image shows its back faces", 0),
      0u)
      << warnings[0];

  const Scene right = box_scene(false);
  const Mesh right_mesh = build_mesh(right);
  EXPECT_TRUE(back_facing_objects(right, right_mesh, RayScene(right_mesh)).empty());
}

}  // namespace
}  // namespace bumprad
