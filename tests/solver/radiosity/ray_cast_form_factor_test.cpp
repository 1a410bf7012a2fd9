// Ray-cast form factors (Wallace et al. 1989) against Lambert's exact point-to-polygon value,
// with and without an occluder, and where the point-to-point kernel would blow up.
#include "solver/radiosity/ray_cast_form_factor.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "solver/radiosity/form_factor_exact.h"
#include "solver/scene/mesh.h"
#include "tests/test_scenes.h"

namespace bumprad {
namespace {

// An n x n grid of sample centres on the w x h rectangle at height z (facing down).
std::vector<AreaSample> grid(double w, double h, double z, int n) {
  std::vector<AreaSample> out;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      out.push_back({Vec3(w * ((i + 0.5) / n - 0.5), h * ((j + 0.5) / n - 0.5), z), w * h / (n * n),
                     Vec3(0, 0, -1)});
  return out;
}

std::vector<Vec3> corners(double w, double h, double z) {
  auto c = test::rectangle_facing_down(w, h, z);
  return {c.begin(), c.end()};
}

TEST(RayCastFormFactor, ConvergesToLambertUnoccluded) {
  const Vec3 up(0, 0, 1), down(0, 0, -1);
  // A receiver below a 1 x 1 source, on axis and off to the side, tilted or not.
  struct Case {
    Vec3 point, normal;
  };
  for (const Case& c : {Case{Vec3(0), up}, Case{Vec3(0.7, 0.2, 0), up},
                        Case{Vec3(0.3, 0, 0.2), glm::normalize(Vec3(0.5, 0, 1))}}) {
    double exact = point_to_polygon(c.point, c.normal, corners(1, 1, 1));
    double previous = 1;
    for (int n : {2, 4, 8, 16}) {
      double f = ray_cast_form_factor(c.point, c.normal, grid(1, 1, 1, n), nullptr, 0);
      double error = std::abs(f - exact) / exact;
      EXPECT_LT(error, previous * 1.01) << "n " << n;  // never worse with more samples
      previous = error;
    }
    EXPECT_LT(previous, 0.01) << "256 samples: within 1%";
  }
}

// Where point sampling fails: a receiver much closer to the source than the samples are
// to each other sees them all at grazing angles. Wallace's dA term keeps every sample finite,
// so the sum stays a form factor, but it falls far short of the exact value (12.7% of it at
// a twentieth of the source's size with 4 x 4 samples). The solver therefore takes near-field
// pairs from the exact value, with only the visibility from the rays.
TEST(RayCastFormFactor, UnderestimatesButStaysFiniteInTheNearField) {
  for (double z : {0.05, 0.01, 0.001}) {
    double f = ray_cast_form_factor(Vec3(0), Vec3(0, 0, 1), grid(1, 1, z, 4), nullptr, 0);
    double exact = point_to_polygon(Vec3(0), Vec3(0, 0, 1), corners(1, 1, z));
    EXPECT_TRUE(std::isfinite(f)) << z;
    EXPECT_GT(f, 0) << z;
    EXPECT_LT(f, 0.15 * exact) << "z " << z;
  }
}

// Half of the source is hidden by a large occluder: only the other half counts.
TEST(RayCastFormFactor, OccludersHideTheirShare) {
  Scene s = test::scene_of(
      {test::quad({Vec3(-5, -5, 1), Vec3(-5, 5, 1), Vec3(0, 5, 1), Vec3(0, -5, 1)})});
  Mesh mesh = build_mesh(s);
  RayScene rays(mesh);
  const Vec3 up(0, 0, 1);
  double half = point_to_polygon(
      Vec3(0), up,
      std::vector<Vec3>{Vec3(0, -0.5, 2), Vec3(0.5, -0.5, 2), Vec3(0.5, 0.5, 2), Vec3(0, 0.5, 2)});
  double f = ray_cast_form_factor(Vec3(0), up, grid(1, 1, 2, 16), &rays, 1e-6);
  EXPECT_NEAR(f, half, 0.01 * half);
  double open = ray_cast_form_factor(Vec3(0), up, grid(1, 1, 2, 16), nullptr, 0);
  EXPECT_NEAR(f, open / 2, 0.01 * open);
}

}  // namespace
}  // namespace bumprad
