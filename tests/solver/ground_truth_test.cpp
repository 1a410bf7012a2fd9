// bumprad's images against the path tracer (solver/path_tracer.cpp) on a small room of its
// own: a ceiling light, a turned block on the floor, a camera that sees the block, its
// shadow and the walls but not the light. Errors are relative RMS over 4 x 4 pixel blocks
// (the lighting varies over many pixels; the blocks average the reference's noise down).
// The reference's own noise there is about 1.7 %; the bounds leave room for it.
#include <cmath>

#include <gtest/gtest.h>

#include "solver/path_tracer.h"
#include "solver/solution.h"

namespace bumprad {
namespace {

Scene small_room(DirectLight direct) {
  Scene s;
  Material white, light;
  white.reflectance = Rgb(0.6, 0.55, 0.5);
  light.reflectance = Rgb(0.6);
  light.emission = Rgb(12);
  s.materials = {white, light};
  Object room;
  room.shape = BoxShape{Vec3(0), Vec3(2, 2, 2), Vec3(0)};
  room.flip_normals = true;
  Object lamp;
  lamp.shape = QuadShape{{Vec3(-0.3, -0.3, 0.999), Vec3(-0.3, 0.3, 0.999), Vec3(0.3, 0.3, 0.999),
                          Vec3(0.3, -0.3, 0.999)}};
  lamp.material = 1;
  Object block;
  block.shape = BoxShape{Vec3(0.25, 0.2, -0.6), Vec3(0.5, 0.5, 0.8), Vec3(0, 0, 25)};
  s.objects = {room, lamp, block};
  s.camera.position = Vec3(-0.2, -0.95, 0.3);
  s.camera.look_at = Vec3(0.1, 0.4, -0.6);
  s.camera.up = Vec3(0, 0, 1);
  s.camera.fov_y_deg = 70;
  s.camera.width = s.camera.height = 48;
  s.camera.antialias = 2;
  s.solver.element_size = 0.25;  // coarse: 8 x 8 elements a wall
  s.solver.max_shots = 5000;
  s.solver.unshot_fraction = 0.002;
  s.solver.direct_light = direct;
  return s;
}

// Relative RMS between 4 x 4 block means.
double block_error(const Image& a, const Image& r) {
  double diff = 0, norm = 0;
  for (int by = 0; by < r.height / 4; ++by)
    for (int bx = 0; bx < r.width / 4; ++bx) {
      Rgb sa(0), sr(0);
      for (int y = 4 * by; y < 4 * by + 4; ++y)
        for (int x = 4 * bx; x < 4 * bx + 4; ++x) sa += a.at(x, y), sr += r.at(x, y);
      for (int c = 0; c < 3; ++c) {
        diff += (sa[c] - sr[c]) * (sa[c] - sr[c]);
        norm += sr[c] * sr[c];
      }
    }
  return std::sqrt(diff / norm);
}

// The reference (1,024 paths a pixel) and a second one with another seed, for its noise.
class GroundTruth : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const Scene scene = small_room(DirectLight::Exact);
    const Mesh mesh = build_mesh(scene);
    const RayScene rays(mesh);
    reference_ = new Image(render_reference(scene, mesh, rays, {1024, 1}));
    second_ = new Image(render_reference(scene, mesh, rays, {1024, 2}));
  }
  static void TearDownTestSuite() {
    delete reference_;
    delete second_;
  }
  static double error_of(DirectLight direct) {
    const Scene scene = small_room(direct);
    return block_error(render(scene, solve(scene)), *reference_);
  }
  static Image* reference_;
  static Image* second_;
};
Image* GroundTruth::reference_ = nullptr;
Image* GroundTruth::second_ = nullptr;

TEST_F(GroundTruth, ReferenceNoiseIsSmall) {
  const double noise = block_error(*second_, *reference_) / std::sqrt(2.0);
  // Measured 1.65 %.
  EXPECT_LT(noise, 0.022);
}

TEST_F(GroundTruth, ExactDirectLightIsCloseToTheReference) {
  const double exact = error_of(DirectLight::Exact);
  const double radiosity = error_of(DirectLight::Radiosity);
  // Measured against this reference (its noise included): exact 2.66 %, radiosity 5.18 %.
  // At element sizes 0.0625, 0.125, 0.25 and 0.5 the two were 1.80/1.98, 2.12/2.74,
  // 2.66/5.18 and 3.90/11.74 %: exact direct light keeps shadows and falloff right on
  // coarse meshes, where interpolated radiosity smears them.
  EXPECT_LT(exact, 0.035);
  EXPECT_LT(radiosity, 0.08);
  EXPECT_GT(radiosity, 1.5 * exact);
}

}  // namespace
}  // namespace bumprad
