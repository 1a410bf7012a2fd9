// Embree over the mesh: a ray meets the element it should at the right distance and side,
// with (u, v) that interpolate back to the hit point; occlusion stops short of `distance`.
#include "solver/scene/ray_scene.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "solver/scene/geometry.h"
#include "tests/test_scenes.h"

namespace bumprad {
namespace {

TEST(RayScene, RaysMeetTheRightElementAtTheRightDistanceAndSide) {
  // A 2 x 2 square at z = 1 facing down, meshed 4 x 4.
  const Mesh mesh =
      build_mesh(test::scene_of({test::quad(test::rectangle_facing_down(2, 2, 1), 4, 4)}));
  const RayScene rays(mesh);
  const Vec3 target(0.3, -0.6, 1);
  const Ray up{{0.3, -0.6, 0}, {0, 0, 1}};
  const auto hit = rays.intersect(up);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 1, 1e-6);
  EXPECT_TRUE(hit->front);
  // The hit's (u, v) put the point back together from the element's corners.
  const Element& e = mesh.elements[hit->element];
  const auto w = corner_weights(e, hit->u, hit->v);
  Vec3 p(0);
  for (int k = 0; k < e.vertex_count; ++k)
    p += w[std::size_t(k)] * mesh.vertices[e.v[std::size_t(k)]].position;
  EXPECT_NEAR(glm::length(p - target), 0, 1e-6);

  const auto back = rays.intersect({{0.3, -0.6, 2}, {0, 0, -1}});
  ASSERT_TRUE(back);
  EXPECT_FALSE(back->front);
  EXPECT_EQ(back->element, hit->element);
  EXPECT_FALSE(rays.intersect({{3, 0, 0}, {0, 0, 1}}));   // beside the square
  EXPECT_FALSE(rays.intersect({{0, 0, 0}, {0, 0, -1}}));  // away from it
}

TEST(RayScene, OcclusionCountsOnlyWhatLiesBeforeTheDistance) {
  const Mesh mesh = build_mesh(test::scene_of({test::quad(test::rectangle_facing_down(2, 2, 1))}));
  const RayScene rays(mesh);
  const Ray up{{0, 0, 0}, {0, 0, 1}};
  EXPECT_TRUE(rays.occluded(up, 1.5));
  EXPECT_FALSE(rays.occluded(up, 0.5));
  EXPECT_TRUE(rays.occluded({{0, 0, 2}, {0, 0, -1}}, 1.5));  // back faces block shadow rays too
}

}  // namespace
}  // namespace bumprad
