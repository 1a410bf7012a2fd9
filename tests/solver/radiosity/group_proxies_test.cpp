// Proxies of a fine model's groups: fewer triangles level by level, on the model's surface
// within the error they report, facing as it does; none where not asked for.
#include "solver/radiosity/group_proxies.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "tests/test_scenes.h"

namespace bumprad {
namespace {

// The distance from p to triangle (a, b, c), by its plane inside it and by its edges outside.
double distance_to(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = glm::normalize(glm::cross(b - a, c - a));
  const Vec3 q = p - glm::dot(p - a, n) * n;
  const bool inside = glm::dot(glm::cross(b - a, q - a), n) >= 0 &&
                      glm::dot(glm::cross(c - b, q - b), n) >= 0 &&
                      glm::dot(glm::cross(a - c, q - c), n) >= 0;
  if (inside) return std::abs(glm::dot(p - a, n));
  auto to_segment = [&](const Vec3& u, const Vec3& v) {
    const double s = std::clamp(glm::dot(p - u, v - u) / glm::dot(v - u, v - u), 0.0, 1.0);
    return glm::length(p - (u + s * (v - u)));
  };
  return std::min({to_segment(a, b), to_segment(b, c), to_segment(c, a)});
}
double distance_to(const Vec3& p, const ProxyTriangle& t) {
  return distance_to(p, Vec3(t.corners[0]), Vec3(t.corners[1]), Vec3(t.corners[2]));
}

const std::array<Vec3, 4> kFloor{Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 0, 0), Vec3(0, 0, 0)};
const Vec3 kCentre(0.5, 0.15, 0.5);
constexpr double kRadius = 0.15;

Mesh ball_on_a_floor() {
  Object ball = test::quad(kFloor);
  ball.shape = test::ball(kCentre, kRadius, 40);
  return build_mesh(test::scene_of({test::quad(kFloor, 4, 4), ball}));
}

// A ball of 6,240 triangles. At every level: each group's vertices lie within the group's
// reported error of that level's proxies (found here over all of them), and its proxy's
// corners as near the ball's triangles; its sphere holds both, the error is under half the level's
// cells (vertices slide along the curved surface to their cluster's point: 0.34-0.46 of a cell
// measured), nearly every proxy triangle faces out as the ball does, and a coarser level halves the
// triangles of the finer one. Skirts lie between two groups.
TEST(GroupProxies, AFineBallsAreFewAndOnItsSurface) {
  const Mesh mesh = ball_on_a_floor();
  const GroupProxies proxies = group_proxies(mesh, std::vector<bool>(mesh.groups.size(), true));
  ASSERT_EQ(proxies.spheres.size(), mesh.groups.size());
  ASSERT_EQ(proxies.levels.size(), 3u);
  const double side = 2 * std::numbers::pi * kRadius / 80;  // about the ball's triangles'
  std::size_t ball_triangles = 0;
  for (const ElementGroup& group : mesh.groups)
    if (mesh.elements[group.first].object == 1) ball_triangles += group.count;
  std::vector<std::size_t> counts;
  for (std::size_t l = 0; l < proxies.levels.size(); ++l) {
    const ProxyLevel& level = proxies.levels[l];
    const double cell = (l == 0 ? 2 : l == 1 ? 4 : 8) * side;
    std::size_t proxied = 0, facing_out = 0;
    double worst = 0;
    for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
      const ProxyLevel::Group& proxy = level.groups[g];
      const ElementGroup& group = mesh.groups[g];
      if (mesh.elements[group.first].object == 0) {
        EXPECT_EQ(proxy.count, 0u) << "the floor's quads are groups of their own";
        continue;
      }
      if (proxy.count == 0) continue;
      ++proxied;
      EXPECT_LT(proxy.error, cell / 2) << "level " << l << ", group " << g;
      worst = std::max(worst, proxy.error / cell);
      const GroupProxies::Sphere& sphere = proxies.spheres[g];
      for (std::uint32_t i = group.first; i < group.first + group.count; ++i) {
        const Element& e = mesh.elements[i];
        for (int k = 0; k < e.vertex_count; ++k) {
          const Vec3& p = mesh.vertices[e.v[std::size_t(k)]].position;
          double nearest = INFINITY;
          for (const ProxyTriangle& t : level.triangles)
            nearest = std::min(nearest, distance_to(p, t));
          EXPECT_LE(nearest, proxy.error + 1e-6) << "level " << l << ", group " << g;
          EXPECT_LE(glm::length(p - sphere.centre), sphere.radius + 1e-9);
        }
      }
      for (std::uint32_t t = proxy.first; t < proxy.first + proxy.count; ++t) {
        const ProxyTriangle& triangle = level.triangles[t];
        facing_out += glm::dot(Vec3(triangle.normal), Vec3(triangle.centroid) - kCentre) > 0;
        EXPECT_EQ(mesh.elements[triangle.element].group, g) << "drawn as one of its elements";
        for (const glm::vec3& corner : triangle.corners) {
          EXPECT_LE(glm::length(Vec3(corner) - sphere.centre), sphere.radius + 1e-6);
          double nearest = INFINITY;  // from the ball's triangles
          for (const Element& e : mesh.elements)
            if (e.object == 1 && glm::length(e.centroid - Vec3(corner)) < 0.1)
              nearest = std::min(nearest, distance_to(Vec3(corner), mesh.vertices[e.v[0]].position,
                                                      mesh.vertices[e.v[1]].position,
                                                      mesh.vertices[e.v[2]].position));
          EXPECT_LE(nearest, proxy.error + 1e-6) << "level " << l << ", group " << g;
        }
      }
      for (std::uint32_t t = proxy.skirt_first; t < proxy.skirt_first + proxy.skirt_count; ++t) {
        EXPECT_NE(level.skirt_neighbour[t], g);
        EXPECT_EQ(mesh.elements[level.skirts[t].element].group, g);
      }
    }
    EXPECT_GT(proxied, 10u) << "level " << l;
    EXPECT_GT(double(facing_out), 0.98 * double(level.triangles.size())) << "level " << l;
    counts.push_back(level.triangles.size());
    std::printf("level %zu: %zu groups, %zu triangles -> %zu, %zu skirts, error %.2f of a cell\n",
                l, proxied, ball_triangles, level.triangles.size(), level.skirts.size(), worst);
  }
  EXPECT_LT(double(counts[0]), 0.5 * double(ball_triangles));
  EXPECT_LT(counts[1], counts[0]);
  EXPECT_LT(counts[2], counts[1]);
}

TEST(GroupProxies, NoneWhereNotAsked) {
  const Mesh mesh = ball_on_a_floor();
  const GroupProxies proxies = group_proxies(mesh, std::vector<bool>(mesh.groups.size(), false));
  for (const ProxyLevel& level : proxies.levels) {
    EXPECT_TRUE(level.triangles.empty());
    EXPECT_TRUE(level.skirts.empty());
  }
}

}  // namespace
}  // namespace bumprad
