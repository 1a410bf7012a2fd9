// Exact direct light against closed forms: with nothing in the way it is Lambert's
// point-to-polygon form factor times E to rounding, for any normal (clipped to its plane)
// and any number of shadow rays; behind a blocker, the emitter's visible part; with fewer
// rays than emitters it is still exact in the open and unbiased in shadow; a penumbra from
// stratified rays is smoother than from independent ones. Statistical bounds are several
// standard errors of the sample counts used.
#include "solver/render/lights.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "solver/radiosity/form_factor_exact.h"

namespace bumprad {
namespace {

constexpr double kE = 3;

// A unit-square emitter at z = 1 facing down over a 4 x 4 floor facing up, both meshed at
// `element_size`; optionally a blocker at z = 0.5 over x < 0 (from a floor point at x = a
// it hides the emitter's part with x < -a).
struct Room {
  Scene scene;
  Mesh mesh;
  std::unique_ptr<RayScene> rays;

  explicit Room(double element_size, bool blocker = false) {
    Material light, white;
    light.emission = Rgb(kE);
    scene.materials = {light, white};
    auto quad = [](std::array<Vec3, 4> p, int material) {
      Object o;
      o.shape = QuadShape{p};
      o.material = material;
      return o;
    };
    scene.objects = {
        quad({Vec3(-0.5, -0.5, 1), Vec3(-0.5, 0.5, 1), Vec3(0.5, 0.5, 1), Vec3(0.5, -0.5, 1)}, 0),
        quad({Vec3(-2, -2, 0), Vec3(2, -2, 0), Vec3(2, 2, 0), Vec3(-2, 2, 0)}, 1)};
    if (blocker)
      scene.objects.push_back(
          quad({Vec3(-2, -2, 0.5), Vec3(-2, 2, 0.5), Vec3(0, 2, 0.5), Vec3(0, -2, 0.5)}, 1));
    scene.solver.element_size = element_size;
    mesh = build_mesh(scene);
    rays = std::make_unique<RayScene>(mesh);
  }

  // E F from x to the part of the emitter with x >= x0.
  double exact(const Vec3& x, const Vec3& n, double x0 = -0.5) const {
    const std::array<Vec3, 4> part = {Vec3(x0, -0.5, 1), Vec3(x0, 0.5, 1), Vec3(0.5, 0.5, 1),
                                      Vec3(0.5, -0.5, 1)};
    return kE * point_to_polygon(x, n, part);
  }

  // What shadow rays to points of the lamp's elements (of `size`) chosen by area find on
  // average at x behind the blocker: each element's E F times the share of its area with
  // x >= x0.
  double area_weighted(const Vec3& x, double x0, double size) const {
    double sum = 0;
    for (double a = -0.5; a < 0.5 - 1e-9; a += size)
      for (double b = -0.5; b < 0.5 - 1e-9; b += size) {
        const std::array<Vec3, 4> e = {Vec3(a, b, 1), Vec3(a, b + size, 1),
                                       Vec3(a + size, b + size, 1), Vec3(a + size, b, 1)};
        sum += kE * point_to_polygon(x, Vec3(0, 0, 1), e) *
               std::clamp((a + size - std::max(a, x0)) / size, 0.0, 1.0);
      }
    return sum;
  }
};

// The mean of `trials` estimates at x on the floor, each with its own seed.
double mean_direct(const Lights& lights, const Room& room, const Vec3& x, int rays, int trials) {
  const Vec3 up(0, 0, 1);
  double sum = 0;
  for (int k = 0; k < trials; ++k) {
    Random random(std::uint64_t(k) + 1);
    sum += lights.direct(x, up, up, *room.rays, ShadowRays{rays, random.bits64()}).g;
  }
  return sum / trials;
}

TEST(Lights, UnoccludedDirectLightIsLambertTimesE) {
  const Room room(0.25);  // 16 emitter elements
  const Lights lights(room.mesh, room.scene.materials);
  const Vec3 up(0, 0, 1);
  for (const Vec3 x : {Vec3(0, 0, 0), Vec3(0.3, -0.2, 0), Vec3(1.9, 1.9, 0)})
    for (int rays : {16, 64}) {
      Random random(7);
      const Rgb d = lights.direct(x, up, up, *room.rays, ShadowRays{rays, random.bits64()});
      EXPECT_NEAR(d.g / room.exact(x, up), 1, 1e-12) << x.x << " " << x.y << " rays " << rays;
    }
}

TEST(Lights, APerturbedNormalClipsTheEmitterToItsPlane) {
  const Room room(0.25);
  const Lights lights(room.mesh, room.scene.materials);
  const Vec3 up(0, 0, 1), x(0.6, 0, 0);
  for (double tilt_deg : {30.0, 60.0, 80.0}) {
    const double t = tilt_deg * std::numbers::pi / 180;
    const Vec3 n(std::sin(t), 0, std::cos(t));  // leaning away from the emitter
    Random random(3);
    const double expected = room.exact(x, n);
    ASSERT_GT(expected, 0);
    EXPECT_LT(expected, room.exact(x, up));
    EXPECT_NEAR(lights.direct(x, n, up, *room.rays, ShadowRays{16, random.bits64()}).g / expected,
                1, 1e-12)
        << tilt_deg;
  }
}

// What the shadow rays found, kept for any normal (a bump's N' to come): the form gives
// direct()'s value for every normal it covers (in single precision), in the open and half in
// shadow, near the lamp (its elements one by one) and far (its outline); it refuses a normal
// whose plane cuts the lamp, for which direct() clips.
TEST(Lights, TheDirectFormGivesTheDirectLightForEveryNormalItCovers) {
  const Room room(0.25, /*blocker=*/true);
  const Lights lights(room.mesh, room.scene.materials);
  const Vec3 up(0, 0, 1);
  int covered = 0, refused = 0;
  for (const Vec3 x : {Vec3(0.1, 0.1, 0), Vec3(0.6, 0, 0), Vec3(1.9, -1.2, 0), Vec3(-1, 0, 0)})
    for (int k = 0; k <= 24; ++k) {
      const double t = (k - 12) * 7 * std::numbers::pi / 180;
      const Vec3 n(std::sin(t), 0, std::cos(t));
      Random a(9), b(9);
      const DirectForm form = lights.direct_form(x, up, *room.rays, ShadowRays{4, a.bits64()});
      const Rgb exact = lights.direct(x, n, up, *room.rays, ShadowRays{4, b.bits64()});
      if (!form.covers(n)) {
        ++refused;
        continue;
      }
      ++covered;
      EXPECT_NEAR(form.at(n).g, exact.g, 1e-6 * std::max(exact.g, 1.0)) << x.x << " tilt " << k;
    }
  EXPECT_GT(covered, 40);
  EXPECT_GT(refused, 4);
  // A normal leaning 80 degrees away from a lamp that stands 60 degrees up is refused.
  Random random(1);
  const DirectForm form =
      lights.direct_form(Vec3(0.6, 0, 0), up, *room.rays, ShadowRays{4, random.bits64()});
  const double t = 80 * std::numbers::pi / 180;
  EXPECT_FALSE(form.covers(Vec3(std::sin(t), 0, std::cos(t))));
}

TEST(Lights, NothingArrivesBehindAnEmitter) {
  const Room room(0.25);
  const Lights lights(room.mesh, room.scene.materials);
  Random random(1);
  EXPECT_EQ(lights.direct(Vec3(0, 0, 2), Vec3(0, 0, -1), Vec3(0, 0, -1), *room.rays,
                          ShadowRays{16, random.bits64()}),
            Rgb(0));
}

TEST(Lights, APartlyHiddenEmitterGivesItsVisiblePart) {
  const Room room(0.25, /*blocker=*/true);
  const Lights lights(room.mesh, room.scene.materials);
  const Vec3 up(0, 0, 1), x(0.1, 0.1, 0);  // the shadow line crosses elements at x = -0.1
  // 64,000 rays, a sixth of them at elements the line crosses: about 0.001 standard error.
  // Measured 0.989 (0.990 at 40,000 calls): a shadow ray picks a point of an element by
  // area, so the share it finds weighs the element's parts by area, not by their form
  // factors, about 1 % dark this near a 1 m lamp.
  EXPECT_NEAR(mean_direct(lights, room, x, 16, 4000) / room.exact(x, up, -0.1), 1, 0.015);
}

TEST(Lights, FewerRaysThanEmittersStayExactInTheOpenAndUnbiasedInShadow) {
  const Vec3 up(0, 0, 1);
  const Room open(0.0625);  // 256 emitter elements, 4 rays a call
  const Lights open_lights(open.mesh, open.scene.materials);
  Random random(5);
  const Vec3 x(1.2, 0.4, 0);
  EXPECT_NEAR(open_lights.direct(x, up, up, *open.rays, ShadowRays{4, random.bits64()}).g /
                  open.exact(x, up),
              1, 1e-12);
  // From afar each patch of the lamp counts as one polygon, its outline: still exact.
  const Vec3 far(6, 0.5, 0);
  EXPECT_NEAR(open_lights.direct(far, up, up, *open.rays, ShadowRays{4, random.bits64()}).g /
                  open.exact(far, up),
              1, 1e-12);

  const Room half(0.0625, /*blocker=*/true);
  const Lights lights(half.mesh, half.scene.materials);
  const Vec3 y(0.1, 0.1, 0);
  // 8,000 rays picked by contribution: about 0.006 standard error.
  EXPECT_NEAR(mean_direct(lights, half, y, 4, 2000) / half.exact(y, up, -0.1), 1, 0.03);
}

// Speckle: across the blocker's penumbra (floor points x in [-0.45, 0.45] see the emitter's
// part x >= -x), one call each at the view pass's 4 shadow rays over the lamp's 16 elements,
// every call its own seed, against 4 rays to independent random points of the lamp (whose
// visibility is known in closed form here), relative RMS over the row.
TEST(Lights, PenumbraeAreSmooth) {
  const Vec3 up(0, 0, 1);
  const Room room(0.25, /*blocker=*/true);
  const Lights lights(room.mesh, room.scene.materials);
  double error = 0, random_error = 0, norm = 0;
  for (int k = 0; k <= 400; ++k) {
    const Vec3 x(-0.45 + 0.9 * k / 400, 0.1, 0);
    Random random(std::uint64_t(k) + 11);
    const double exact = room.exact(x, up, -x.x);
    const double got = lights.direct(x, up, up, *room.rays, ShadowRays{4, random.bits64()}).g;
    int hits = 0;
    for (int r = 0; r < 4; ++r) hits += random.next() - 0.5 >= -x.x;
    const double independent = room.exact(x, up) * hits / 4;
    error += (got - exact) * (got - exact);
    random_error += (independent - exact) * (independent - exact);
    norm += exact * exact;
  }
  // Measured: 0.19 against 0.38 (0.27 without the penumbra's extra rays).
  EXPECT_LT(std::sqrt(error / norm), 0.6 * std::sqrt(random_error / norm));
}

// The edge of a penumbra: floor points x in [0.40, 0.49] where the blocker hides a strip of
// the lamp 1-10 % wide along its side (x < -x). When the first of a few stratified points
// decided whether a point lay in a penumbra, they mostly missed such a strip and read the
// point as wholly lit: a bright band along every penumbra, a bias that no count of seeds
// averages out. Shadow rays to the lamp's corners find the strip whatever its width, and
// the penumbra's rays, at a random shift, are then unbiased but for the area weighting
// (Lights.APartlyHiddenEmitterGivesItsVisiblePart: a little dark this near the lamp). Mean
// signed error over the row and 40 seeds a point, relative, at the view pass's 4 rays: its
// standard error about 0.1 %.
TEST(Lights, APenumbrasEdgeIsNotReadAsWhollyLit) {
  const Vec3 up(0, 0, 1);
  const Room room(0.25, /*blocker=*/true);
  const Lights lights(room.mesh, room.scene.materials);
  double bias = 0;
  constexpr int kPoints = 46, kSeeds = 40;
  for (int k = 0; k < kPoints; ++k) {
    const Vec3 x(0.40 + 0.002 * k, 0.1, 0);
    const double exact = room.exact(x, up, -x.x);
    for (int seed = 0; seed < kSeeds; ++seed) {
      const ShadowRays shadow{4, hash64(std::uint64_t(k * kSeeds + seed))};
      bias += (lights.direct(x, up, up, *room.rays, shadow).g - exact) / exact;
    }
  }
  bias /= kPoints * kSeeds;
  // Measured: -0.51 % (-0.5 % at 4,000 seeds a point); with the first 4 points deciding,
  // +1.4 %.
  EXPECT_LT(bias, 0.002);
  EXPECT_GT(bias, -0.01);
}

// A pixel's hits share one sequence, each taking its own blocks of it (ShadowRays): across
// the same penumbra, the mean of a pixel's 4 hits (at one point, so that only the shadow
// rays differ) against the mean of 4 hits that each shift the sequence their own way, as
// hits did before they shared it; relative RMS over the row about what the rays find on
// average (the area weighting's bias, which both share, left out), for a lamp of one
// element and of 16.
TEST(Lights, APixelsHitsStratifyTheLightTogether) {
  const Vec3 up(0, 0, 1);
  for (double size : {1.0, 0.25}) {
    const Room room(size, /*blocker=*/true);
    const Lights lights(room.mesh, room.scene.materials);
    constexpr std::uint32_t kHits = 4;
    double shared = 0, own = 0, norm = 0;
    for (int k = 0; k <= 400; ++k) {
      const Vec3 x(-0.45 + 0.9 * k / 400, 0.1, 0);
      const double exact = room.area_weighted(x, -x.x, size);
      double together = 0, apart = 0;
      for (std::uint32_t hit = 0; hit < kHits; ++hit) {
        together += lights.direct(x, up, up, *room.rays, ShadowRays{4, hash64(k), hit}).g;
        apart += lights.direct(x, up, up, *room.rays, ShadowRays{4, hash64(k * kHits + hit)}).g;
      }
      shared += std::pow(together / kHits - exact, 2);
      own += std::pow(apart / kHits - exact, 2);
      norm += exact * exact;
    }
    // Measured: 0.028 against 0.045 (one element, 16 rays a hit), 0.030 against 0.039 (16
    // elements, one ray each a hit, where the hits' nets stratify each element 4-fold).
    EXPECT_LT(std::sqrt(shared / norm), 0.9 * std::sqrt(own / norm)) << size;
  }
}

}  // namespace
}  // namespace bumprad
