// The map's bases against closed forms: the sampled normals' interpolation weights, and
// the harmonics' reconstruction of the clamped cosine (one distant light) and of a uniform
// sky, at tilts up to 90 degrees, and of a lamp's clipped form factor.
#include "solver/radiosity/map_basis.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "solver/radiosity/form_factor_exact.h"

namespace bumprad {
namespace {

constexpr double kPi = std::numbers::pi;

MapSettings settings_of(MapBasisKind kind) {
  MapSettings s;
  s.basis = kind;
  return s;
}

// B' at `normal` of the values in `values`.
double evaluate(const MapBasis& basis, const std::vector<double>& values, const Vec3& normal) {
  const MapTerms t = basis.evaluate(normal);
  double b = 0;
  for (int i = 0; i < t.count; ++i) b += t.weight[std::size_t(i)] * values[t.index[std::size_t(i)]];
  return b;
}

Vec3 spherical(double tilt, double azimuth) {
  return {std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt)};
}

TEST(MapBasis, SeventeenSampledNormalsAndExactWeightsAtThem) {
  const MapBasis basis(settings_of(MapBasisKind::SampledNormals));
  ASSERT_EQ(basis.size(), 17u);
  for (std::size_t s = 0; s < basis.size(); ++s) {
    const MapTerms t = basis.evaluate(basis.sample_directions()[s]);
    double at_s = 0, total = 0;
    for (int i = 0; i < t.count; ++i) {
      total += t.weight[std::size_t(i)];
      if (t.index[std::size_t(i)] == s) at_s += t.weight[std::size_t(i)];
    }
    EXPECT_NEAR(total, 1, 1e-12);
    EXPECT_NEAR(at_s, 1, 1e-9) << s;
  }
  // Beyond the outer ring (and below the tangent plane): clamped to the outer ring.
  const MapTerms t = basis.evaluate(Vec3(1, 0, -0.2));
  ASSERT_EQ(t.count, 2);
  EXPECT_EQ(t.index[0], 9u);
  EXPECT_NEAR(t.weight[0], 1, 1e-12);
}

TEST(MapBasis, TheConstantIsOneAtEveryNormal) {
  for (MapBasisKind kind : {MapBasisKind::SphericalHarmonics, MapBasisKind::SampledNormals}) {
    const MapBasis basis(settings_of(kind));
    const std::vector<double> one(basis.constant().begin(), basis.constant().end());
    for (double tilt : {0.0, 0.3, 0.8, 1.2, 1.5})
      for (double az : {0.0, 1.0, 2.5, 4.0})
        EXPECT_NEAR(evaluate(basis, one, spherical(tilt, az)), 1, 1e-12) << int(kind);
  }
}

// One distant light from w: B'(N') must be max(0, N'.w), the clamped cosine that bands
// 0-2 and 4 approximate. A point light is the worst case for harmonics (bands 0-2 alone
// are off by up to about 9 % of the peak, Ramamoorthi & Hanrahan 2001).
TEST(MapBasis, HarmonicsHoldOneDistantLightsCosineWithinAFewPercent) {
  const MapBasis basis(settings_of(MapBasisKind::SphericalHarmonics));
  ASSERT_EQ(basis.size(), 18u);
  std::vector<double> values(basis.size());
  double worst = 0;
  for (double light_tilt : {0.0, 0.5, 1.0, 1.4, 1.55})
    for (double tilt = 0; tilt <= kPi / 2 + 1e-9; tilt += kPi / 24)
      for (double az = 0; az < 2 * kPi; az += kPi / 8) {
        const Vec3 w = spherical(light_tilt, 0.3), n = spherical(tilt, az);
        basis.project(w, values);
        worst =
            std::max(worst, std::abs(evaluate(basis, values, n) - std::max(0.0, glm::dot(n, w))));
      }
  std::printf("harmonics, one distant light: worst |B' - max(0, N'.w)| = %.3f\n", worst);
  EXPECT_LT(worst, 0.08);  // of a peak of 1; measured 0.059
}

// A uniform sky of radiosity 1 over the upper hemisphere: B'(N') = (1 + cos tilt) / 2, the
// view factor from a tilted plane to the sky (by a fine quadrature of project()).
TEST(MapBasis, BothBasesHoldAUniformSky) {
  for (MapBasisKind kind : {MapBasisKind::SphericalHarmonics, MapBasisKind::SampledNormals}) {
    const MapBasis basis(settings_of(kind));
    std::vector<double> values(basis.size(), 0.0), p(basis.size());
    constexpr int kN = 400;  // midpoint rule in cos(theta) and azimuth: dw / pi = d(cos) dphi / pi
    for (int i = 0; i < kN; ++i)
      for (int j = 0; j < 2 * kN; ++j) {
        const double z = (i + 0.5) / kN, r = std::sqrt(1 - z * z), phi = kPi * (j + 0.5) / kN;
        basis.project(Vec3(r * std::cos(phi), r * std::sin(phi), z), p);
        for (std::size_t k = 0; k < p.size(); ++k)
          values[k] += p[k] * (1.0 / kN) * (kPi / kN) / kPi;
      }
    double worst = 0;
    const double reach = kind == MapBasisKind::SphericalHarmonics ? kPi / 2 : kPi / 4;
    for (double tilt = 0; tilt <= reach + 1e-9; tilt += reach / 8)
      for (double az : {0.0, 0.7, 2.0})
        worst = std::max(worst, std::abs(evaluate(basis, values, spherical(tilt, az)) -
                                         (1 + std::cos(tilt)) / 2));
    std::printf("uniform sky (%d): worst error %.2e\n", int(kind), worst);
    // Measured: harmonics 4e-7 (the sky's odd bands above 1 are what A_l removes anyway),
    // samples 9.4e-3 (linear between rings).
    EXPECT_LT(worst, kind == MapBasisKind::SphericalHarmonics ? 1e-5 : 1.5e-2);
  }
}

// A lamp's direct light at every tilt (its clipped form factor, form_factor_exact.h), as
// project_polygon() puts it into each basis: exact at the samples for sampled normals (up
// to the quadrature), and in harmonics within their band limit, worst for a small lamp (a
// point light's clamped cosine is off by up to 0.059 of its peak, above) and where N' cuts
// a lamp near by.
TEST(MapBasis, APolygonsClippedFormFactorAtEveryTilt) {
  struct Lamp {
    double half, height, offset;
  };
  for (MapBasisKind kind : {MapBasisKind::SphericalHarmonics, MapBasisKind::SampledNormals}) {
    const MapBasis basis(settings_of(kind));
    std::vector<double> values(basis.size());
    for (const Lamp lamp :
         {Lamp{0.05, 1, 0}, Lamp{0.3, 1, 0.8}, Lamp{1, 0.5, 0.3}, Lamp{2, 0.2, 0}}) {
      // A square facing down, lamp.offset along x from straight above (any winding).
      const std::vector<Vec3> square = {{lamp.offset - lamp.half, -lamp.half, lamp.height},
                                        {lamp.offset + lamp.half, -lamp.half, lamp.height},
                                        {lamp.offset + lamp.half, lamp.half, lamp.height},
                                        {lamp.offset - lamp.half, lamp.half, lamp.height}};
      basis.project_polygon(square, values);
      const double peak = point_to_polygon(Vec3(0), glm::normalize(square[0] + square[2]), square);
      double worst = 0;
      const auto check = [&](const Vec3& n) {
        worst = std::max(
            worst,
            std::abs(evaluate(basis, values, n) - point_to_polygon(Vec3(0), n, square)) / peak);
      };
      if (kind == MapBasisKind::SampledNormals) {
        for (const Vec3& n : basis.sample_directions()) check(n);
      } else {
        for (double tilt = 0; tilt <= kPi / 2 + 1e-9; tilt += kPi / 24)
          for (double az = 0; az < 2 * kPi; az += kPi / 8) check(spherical(tilt, az));
      }
      std::printf("basis %d, lamp %.2f at %.1f: worst error %.2e of the peak\n", int(kind),
                  lamp.half, lamp.height, worst);
      // Measured: harmonics 0.048 (the smallest lamp) to 0.0027; samples 1.2e-4 at most.
      EXPECT_LT(worst, kind == MapBasisKind::SphericalHarmonics ? 0.06 : 3e-4) << lamp.half;
    }
  }
}

}  // namespace
}  // namespace bumprad
