// Geometry helpers against shapes whose answer is known by construction.
#include "solver/scene/geometry.h"

#include <algorithm>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

namespace bumprad {
namespace {

// The hull of points in a tilted plane: an L-shaped region's corners, points on its edges
// and inside it; the hull keeps five corners and leaves the reflex one out.
TEST(ConvexHull, KeepsTheOutermostCornersOfPointsInAPlane) {
  const Vec3 normal = glm::normalize(Vec3(1, 2, 3));
  const Vec3 u = glm::normalize(glm::cross(normal, Vec3(0, 0, 1))), v = glm::cross(normal, u);
  const auto at = [&](double a, double b) { return Vec3(5, -1, 2) + a * u + b * v; };
  // L: (0,0) (2,0) (2,1) (1,1) (1,2) (0,2), the reflex corner (1,1); and inner points.
  const std::vector<Vec3> points = {at(0, 0),     at(2, 0), at(2, 1),     at(1, 1),
                                    at(1, 2),     at(0, 2), at(0.5, 0.5), at(1.5, 0.5),
                                    at(0.5, 1.5), at(1, 0), at(0, 1)};
  const std::vector<Vec3> hull = convex_hull(points, normal);
  ASSERT_EQ(hull.size(), 5u);
  for (const Vec3& corner : {at(0, 0), at(2, 0), at(2, 1), at(1, 2), at(0, 2)})
    EXPECT_TRUE(std::any_of(hull.begin(), hull.end(),
                            [&](const Vec3& h) { return glm::length(h - corner) < 1e-12; }));
  // Counter-clockwise about the normal.
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const Vec3& a = hull[k];
    const Vec3& b = hull[(k + 1) % hull.size()];
    const Vec3& c = hull[(k + 2) % hull.size()];
    EXPECT_GT(glm::dot(glm::cross(b - a, c - b), normal), 0);
  }
}

}  // namespace
}  // namespace bumprad
