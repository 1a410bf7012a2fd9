// Which objects shoot as clusters, and how their light leaves them.
#include "solver/radiosity/clusters.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "solver/radiosity/vertex_radiosity.h"
#include "solver/scene/ray_scene.h"
#include "solver/util/math.h"
#include "solver/util/random.h"
#include "tests/test_scenes.h"

namespace bumprad {
namespace {

Object ball_object(const Vec3& centre, double r, int material = 0) {
  Object o;
  o.shape = test::ball(centre, r, 16);
  o.material = material;
  return o;
}

// A 4 m floor and, standing on it, objects that are clusters and objects that are not.
Scene cluster_candidates() {
  const double r = 0.12;
  Object dented = ball_object(Vec3(1.4, r, 1.4), r);
  for (Vec3& p : std::get<TriangleMeshShape>(dented.shape).positions)
    if (std::abs(p.y - r) < 1e-9) p = Vec3(1.4, r, 1.4) + 0.7 * (p - Vec3(1.4, r, 1.4));
  Object bowl = ball_object(Vec3(1.8, r, 1.8), r);
  auto& triangles = std::get<TriangleMeshShape>(bowl.shape).triangles;
  triangles.erase(triangles.begin(), triangles.begin() + std::ptrdiff_t(triangles.size() / 2));
  Object box;
  box.shape = BoxShape{Vec3(2.2, 0.1, 2.2), Vec3(0.2), Vec3(0)};
  Scene s = test::scene_of(
      {test::quad({Vec3(0, 0, 0), Vec3(0, 0, 4), Vec3(4, 0, 4), Vec3(4, 0, 0)}, 8, 8),
       ball_object(Vec3(0.6, r, 0.6), r), ball_object(Vec3(1.0, r, 1.0), r, 1),
       ball_object(Vec3(3.0, 0.5, 3.0), 0.5), ball_object(Vec3(2.6, r, 2.6), r, 2), dented, bowl,
       box});
  s.materials.push_back(test::emitter(5));
  Material mirror;
  mirror.specular = 1;
  s.materials.push_back(mirror);
  return s;
}

// Objects 1 (a small ball) and 2 (a small glowing ball) are clusters; not the floor (one
// flat patch), the large ball (3), the mirror ball (4), the dented ball (5, concave at its
// waist), the bowl (6, a ball's lower half: open) or the box (7, flat faces).
TEST(Clusters, ASmallClosedConvexCurvedDiffuseObjectIsOneAndNothingElseIs) {
  const Scene s = cluster_candidates();
  const Mesh mesh = build_mesh(s);
  const std::vector<Cluster> clusters = find_clusters(mesh, s.materials);
  ASSERT_EQ(clusters.size(), 2u);
  EXPECT_EQ(clusters[0].object, 1u);
  EXPECT_EQ(clusters[1].object, 2u);
  for (const Cluster& c : clusters) {
    EXPECT_GE(c.patches.size(), 2u);
    for (std::uint32_t p : c.patches)
      EXPECT_EQ(mesh.elements[mesh.patches[p].first].object, c.object);
    EXPECT_NEAR(c.radius, 0.12, 1e-3);
  }
  EXPECT_NEAR(glm::length(clusters[0].centre - Vec3(0.6, 0.12, 0.6)), 0, 1e-3);
}

// A ball sunk halfway into a block has its centre in the block's top face and half of it
// buried (vertex_radiosity.h's open shares): not a cluster, whose lower half hemi-cube would
// look through the block's culled faces into the room; it would be one were it all open. A
// ball resting on the floor beside the block is one.
TEST(Clusters, ABallSunkIntoABlockIsNotOne) {
  const double r = 0.12;
  Object room, block;
  room.shape = BoxShape{Vec3(2, 1.5, 2), Vec3(4, 3, 4), Vec3(0)};
  room.flip_normals = true;
  block.shape = BoxShape{Vec3(3, 0.25, 3), Vec3(0.5), Vec3(0)};
  const Scene s =
      test::scene_of({room, block, ball_object(Vec3(1, r, 1), r), ball_object(Vec3(3, 0.5, 3), r)});
  const Mesh mesh = build_mesh(s);
  const RayScene rays(mesh);
  const OpenParts open = open_parts(mesh, rays);
  EXPECT_EQ(find_clusters(mesh, s.materials).size(), 2u);
  const std::vector<Cluster> clusters = find_clusters(mesh, s.materials, open.share);
  ASSERT_EQ(clusters.size(), 1u);
  EXPECT_EQ(clusters[0].object, 2u);
}

// Each member's lobes carry all its light (their lengths sum to 1), and a uniformly bright
// ball's members, weighed by their areas, send every direction the same: 1 / (4 pi) of its
// light per steradian. Measured over 2,000 directions: -0.02 % on average, worst 4.5 %; with
// each member's light as one cosine lobe (its normals summed, not binned), which misses a
// curved patch's spread, +0.17 % and 32 %.
TEST(Clusters, AMembersLobesCarryAllItsLightAndAUniformBallsLightIsEven) {
  const Scene s = cluster_candidates();
  const Mesh mesh = build_mesh(s);
  const Cluster ball = find_clusters(mesh, s.materials).at(0);
  std::vector<std::vector<Vec3>> lobes;
  std::vector<double> share;
  double area = 0;
  for (std::uint32_t p : ball.patches) {
    const Patch& patch = mesh.patches[p];
    lobes.push_back(member_lobes(mesh, patch, std::vector<double>(patch.count, 0.0)));
    double length = 0;
    for (const Vec3& lobe : lobes.back()) length += glm::length(lobe);
    EXPECT_NEAR(length, 1, 1e-12);
    share.push_back(patch.area);
    area += patch.area;
  }
  MersenneTwister rng(7);
  double worst = 0, mean = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const double z = 2 * rng.next() - 1, phi = 2 * kPi * rng.next();
    const Vec3 w(std::sqrt(1 - z * z) * std::cos(phi), z, std::sqrt(1 - z * z) * std::sin(phi));
    double intensity = 0;  // per steradian, of the ball's light
    for (std::size_t m = 0; m < lobes.size(); ++m)
      for (const Vec3& lobe : lobes[m])
        intensity += share[m] / area * std::max(0.0, glm::dot(lobe, w)) / kPi;
    const double error = intensity * 4 * kPi - 1;
    worst = std::max(worst, std::abs(error));
    mean += error / n;
  }
  std::printf("a uniform ball's intensity: mean %+.2f %%, worst %.2f %%\n", 100 * mean,
              100 * worst);
  EXPECT_LT(std::abs(mean), 0.01);
  EXPECT_LT(worst, 0.05);
}

}  // namespace
}  // namespace bumprad
