// The closed forms agree with each other and with published values (Howell's catalogue).
#include "solver/radiosity/form_factor_exact.h"
#include "solver/util/random.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "solver/scene/geometry.h"
#include "tests/test_scenes.h"

namespace bumprad {
namespace {

// Differential area below the corner of a parallel a x b rectangle at distance c (Howell B-3).
double corner_point_to_rectangle(double a, double b, double c) {
  double A = a / c, B = b / c, a1 = std::sqrt(1 + A * A), b1 = std::sqrt(1 + B * B);
  return (A / a1 * std::atan(B / a1) + B / b1 * std::atan(A / b1)) / (2 * std::numbers::pi);
}

// Lambert's formula takes its angles from angle(), a rational approximation: it agrees with
// std::atan2 to 1e-15 over eighteen decades of both arguments, and at the axes.
TEST(FormFactorExact, AngleIsAtan2ForNonNegativeY) {
  Random random(7);
  auto uniform = [](Random& r) { return 2 * r.next() - 1; };
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    const double y = std::abs(uniform(random)) * std::pow(10.0, 9 * uniform(random));
    const double x = uniform(random) * std::pow(10.0, 9 * uniform(random));
    worst = std::max(worst, std::abs(angle(y, x) - std::atan2(y, x)));
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_EQ(angle(0, 1), 0.0);
  EXPECT_DOUBLE_EQ(angle(0, -1), std::numbers::pi);
  EXPECT_DOUBLE_EQ(angle(1, 0), std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(angle(1, 1), std::numbers::pi / 4);
}

TEST(FormFactorExact, PublishedUnitSquareValues) {
  EXPECT_NEAR(parallel_rectangles(1, 1, 1), 0.19982, 1e-5);
  EXPECT_NEAR(perpendicular_rectangles(1, 1, 1), 0.20004, 1e-5);
}

TEST(FormFactorExact, LambertMatchesCornerFormulaAtTheCentreOfASquare) {
  auto square = test::rectangle_facing_down(1, 1, 1);
  double lambert = point_to_polygon(Vec3(0), Vec3(0, 0, 1), square);
  EXPECT_NEAR(lambert, 4 * corner_point_to_rectangle(0.5, 0.5, 1), 1e-12);
  EXPECT_NEAR(lambert, 0.2395, 1e-4);  // the proximity example of docs/architecture.md
}

TEST(FormFactorExact, LambertIsIndependentOfWinding) {
  auto square = test::rectangle_facing_down(2, 1, 0.7);
  std::array<Vec3, 4> reversed = {square[3], square[2], square[1], square[0]};
  Vec3 n = glm::normalize(Vec3(0.3, -0.2, 1));
  EXPECT_NEAR(point_to_polygon(Vec3(0.1, 0, 0), n, square),
              point_to_polygon(Vec3(0.1, 0, 0), n, reversed), 1e-14);
}

// Lambert's formula is linear in the normal while the polygon stays wholly in front of it:
// one vector then gives the form factor for every such normal (either winding), to rounding.
TEST(FormFactorExact, TheVectorFormFactorGivesLambertForEveryNormalInFront) {
  auto square = test::rectangle_facing_down(2, 1, 0.7);
  std::array<Vec3, 4> reversed = {square[3], square[2], square[1], square[0]};
  const Vec3 x(0.3, -0.1, 0);
  const Vec3 phi = polygon_vector(x, square);
  EXPECT_NEAR(glm::length(phi - polygon_vector(x, reversed)), 0, 1e-15);
  Random random(11);
  int tried = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 n =
        glm::normalize(Vec3(2 * random.next() - 1, 2 * random.next() - 1, 2 * random.next() - 1));
    if (!std::all_of(square.begin(), square.end(),
                     [&](const Vec3& c) { return glm::dot(n, c - x) > 0; }))
      continue;
    ++tried;
    EXPECT_NEAR(glm::dot(n, phi), point_to_polygon(x, n, square), 1e-14);
  }
  EXPECT_GT(tried, 100);
  // A normal whose plane cuts the polygon sees less than the linear form says.
  const Vec3 grazing(1, 0, 0.05);
  EXPECT_GT(point_to_polygon(x, glm::normalize(grazing), square),
            glm::dot(glm::normalize(grazing), phi) + 1e-3);
}

TEST(FormFactorExact, ClippingAtTheHorizon) {
  // A receiver normal tilted 90 degrees sees exactly half of a centred square: the
  // half-space cut passes through the square's centre line.
  auto square = test::rectangle_facing_down(1, 1, 1);
  double half = point_to_polygon(Vec3(0), Vec3(1, 0, 0), square);
  // By symmetry, x-facing sees the x > 0 half with weight cos = x / r.
  // Check against a fine midpoint quadrature of cos(theta) / (pi r^2) cos(theta_j).
  double sum = 0;
  const int n = 1000;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double x = 0.5 * (i + 0.5) / n, y = -0.5 + (j + 0.5) / n;
      double r2 = x * x + y * y + 1;
      sum += (x / std::sqrt(r2)) * (1 / std::sqrt(r2)) / (std::numbers::pi * r2) * (0.5 / n) *
             (1.0 / n);
    }
  EXPECT_NEAR(half, sum, 1e-6);
  EXPECT_EQ(point_to_polygon(Vec3(0), Vec3(0, 0, -1), square), 0.0);
}

// An element far from a point (kSmallPatchRadii of its radius or more) is taken as a small
// patch, A cos cos / (pi r^2): off Lambert's by at most 1.5 (radius / r)^2 (measured: 1.43,
// where the element is seen at grazing angles; 1.0 head on), so by 2.3 % where it takes
// over and less further out; nearer, Lambert's own value; one-sided at any distance.
TEST(FormFactorExact, AnElementFarFromAPointIsASmallPatch) {
  Mesh mesh;
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(0.2, 0, 0), Vec3(0.2, 0.1, 0), Vec3(0, 0.1, 0)})
    mesh.vertices.push_back({p, Vec3(0, 0, 1), {}, {}, {}});
  Element e;
  e.v = {0, 1, 2, 3};
  ASSERT_TRUE(compute_element_geometry(mesh.vertices, e));
  const double radius = element_radius(mesh, e);
  EXPECT_NEAR(radius, std::sqrt(0.1 * 0.1 + 0.05 * 0.05), 1e-12);
  std::array<Vec3, 4> storage;
  const auto corners = element_corners(mesh, e, storage);
  Random random(3);
  double worst_near = 0, worst_far = 0;
  for (int i = 0; i < 2000; ++i) {
    // Points above the element's plane at 1 to 12 radii, with receiver normals facing it.
    const Vec3 dir =
        glm::normalize(Vec3(2 * random.next() - 1, 2 * random.next() - 1, 0.05 + random.next()));
    const double r = radius * (1 + 11 * random.next());
    const Vec3 point = e.centroid + r * dir;
    const Vec3 normal =
        glm::normalize(-dir + 0.5 * Vec3(random.next() - 0.5, random.next() - 0.5, 0));
    const double lambert = point_to_polygon(point, normal, corners);
    const double f = point_to_element(mesh, e, radius, point, normal);
    if (r <= kSmallPatchRadii * radius) {
      worst_near = std::max(worst_near, std::abs(f - lambert));
    } else if (lambert > 1e-12) {
      const double bound = (radius / r) * (radius / r);
      worst_far = std::max(worst_far, std::abs(f / lambert - 1) / bound);
    }
    EXPECT_EQ(point_to_element(mesh, e, radius, e.centroid - r * dir, dir), 0.0);  // behind
  }
  EXPECT_EQ(worst_near, 0.0);
  EXPECT_GT(worst_far, 0.0);  // the far value is an approximation, ...
  EXPECT_LT(worst_far, 1.5);  // ... within 1.5 (radius / r)^2 of Lambert's
}

// The part of a unit square in front of a plane: none, a half along a diagonal, a third
// across it, all of it.
TEST(FormFactorExact, TheAreaInFrontOfAPlaneIsTheClippedPolygons) {
  const std::array<Vec3, 4> square = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  EXPECT_NEAR(area_in_front(Vec3(0, 0, 2), Vec3(0, 0, 1), square), 0, 1e-12);
  EXPECT_NEAR(area_in_front(Vec3(0, 0, 0), glm::normalize(Vec3(1, -1, 0)), square), 0.5, 1e-12);
  EXPECT_NEAR(area_in_front(Vec3(0, 2.0 / 3, 0), Vec3(0, 1, 0), square), 1.0 / 3, 1e-12);
  EXPECT_NEAR(area_in_front(Vec3(0, 0, -1), Vec3(0, 0.6, 0.8), square), 1, 1e-12);
}

}  // namespace
}  // namespace bumprad
