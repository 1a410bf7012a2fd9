// Whole solves through the library call: re-texturing a solution with another bump
// function gives the pixels of a fresh solve with that function, and a flat bump gives the
// plain render.
#include "solver/solution.h"

#include <cmath>
#include <memory>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "tests/test_scenes.h"

namespace bumprad {
namespace {

// A lamp above a floor, with a sphere (curved) and a tilted box that may carry bumps.
Scene bumpy_scene(TextureMode mode) {
  auto lamp = test::rectangle_facing_down(0.6, 0.6, 2.5);
  auto f = test::rectangle_facing_down(4, 4, 0);
  Scene s =
      test::scene_of({test::quad(lamp, 2, 2, 1), test::quad({f[3], f[2], f[1], f[0]}, 8, 8)}, 0.6);
  s.materials.push_back(test::emitter(30));
  Object sphere;
  sphere.shape = SphereShape{Vec3(-0.6, 0, 0.5), 0.5};
  sphere.density.counts = {24, 12};
  sphere.bump = 0;
  Object box;
  box.shape = BoxShape{Vec3(0.7, 0.2, 0.4), Vec3(0.6, 0.6, 0.8), Vec3(0, 0, 25)};
  box.density.counts = {6, 6};
  box.bump = 1;
  s.objects.push_back(sphere);
  s.objects.push_back(box);
  BumpFunction a, b;
  a.type = BumpType::Wrinkles;
  a.amplitude = 0.02;
  a.scale = {8, 8};
  b.type = BumpType::Dimples;
  b.amplitude = 0.03;
  b.scale = {5, 5};
  s.bumps = {a, b};
  s.camera.position = Vec3(0, -4, 2.5);
  s.camera.look_at = Vec3(0, 0, 0.4);
  s.camera.up = Vec3(0, 0, 1);
  s.camera.width = 96;
  s.camera.height = 64;
  s.solver.max_shots = 60;
  s.solver.texture = mode;
  return s;
}

double max_difference(const Image& a, const Image& b) {
  double d = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i)
    d = std::max(d, double(std::abs(a.rgb[i] - b.rgb[i])));
  return d;
}

TEST(Solution, RetexturingEqualsAFreshSolveWithTheNewBumps) {
  for (TextureMode mode : {TextureMode::Gather, TextureMode::Shoot}) {
    Scene with_a = bumpy_scene(mode);
    Scene with_b = with_a;
    std::swap(with_b.bumps[0], with_b.bumps[1]);
    with_b.bumps[1].amplitude = 0.05;
    Solution solved_a = solve(with_a);
    Image retextured = render(with_b, solved_a);
    Image fresh = render(with_b, solve(with_b));
    EXPECT_EQ(retextured.rgb, fresh.rgb) << "mode " << int(mode);
    EXPECT_GT(max_difference(retextured, render(with_a, solved_a)), 0.01) << "bumps show";
  }
}

// A view kept across re-textures (SolutionView) gives, for every bump function, the image a
// fresh render gives, to the bit: with a mirror that shows the bumps (its rays are traced
// again), adaptive antialiasing (edges the new bumps make are refined anew), tilts so large
// that the lamp crosses N''s horizon (the direct light's form gives way to Lambert's clipped
// formula) and a render stopped half-way before them.
TEST(Solution, AKeptViewRetexturesAsAFreshRenderWould) {
  Scene s = bumpy_scene(TextureMode::Shoot);
  Material mirror;
  mirror.reflectance = Rgb(0.05);
  mirror.specular = 0.9;
  s.materials.push_back(mirror);
  s.objects.push_back(
      test::quad({Vec3(-2, 1.5, 0), Vec3(2, 1.5, 0), Vec3(2, 1.5, 1.5), Vec3(-2, 1.5, 1.5)}, 2, 2,
                 int(s.materials.size()) - 1));
  s.camera.antialias = 2;
  const Solution solution = solve(s);
  const SolutionView view(s, solution);
  std::stop_source stop;
  stop.request_stop();
  view.render(s.bumps, stop.get_token());
  std::vector<std::vector<BumpFunction>> sequence(4, s.bumps);
  sequence[1][0].type = BumpType::Bricks;
  sequence[1][1].amplitude = 0.08;
  for (BumpFunction& b : sequence[2]) b.amplitude = 10;
  for (const auto& bumps : sequence) {
    Scene fresh = s;
    fresh.bumps = bumps;
    EXPECT_EQ(view.render(bumps).rgb, render(fresh, solution).rgb);
  }
  EXPECT_GT(max_difference(view.render(sequence[1]), view.render(sequence[0])), 0.01);
  EXPECT_GT(view.bytes(), std::size_t(s.camera.width * s.camera.height) * sizeof(float));
}

TEST(Solution, PreviewsShowBumpsFromTheFirstStepWhenShooting) {
  Scene s = bumpy_scene(TextureMode::Shoot);
  s.solver.preview_every = 5;
  Scene flat = s;
  for (BumpFunction& b : flat.bumps) b.amplitude = 0;
  int steps = 0;
  solve(s, [&](const Snapshot& snap, const Solution& partial) {
    if (++steps == 1) {
      EXPECT_EQ(snap.shots, 5);
      Image bumpy = render(s, partial, snap);
      EXPECT_GT(max_difference(bumpy, render(flat, partial, snap)), 0.01);
    }
    return true;
  });
  EXPECT_EQ(steps, 60 / 5);
}

// A cancelled job: the stop is seen after the shot in flight, and no final step follows.
TEST(Solution, AStopEndsTheSolveWithinOneShot) {
  Scene s = bumpy_scene(TextureMode::Shoot);
  s.solver.preview_every = 1;
  std::stop_source before;
  before.request_stop();
  int steps = 0;
  Solution none = solve(
      s, [&](const Snapshot&, const Solution&) { return ++steps > 0; }, before.get_token());
  EXPECT_EQ(none.stats.shots, 0);
  EXPECT_EQ(steps, 0);

  std::stop_source during;
  Solution partial = solve(
      s,
      [&](const Snapshot& snap, const Solution&) {
        ++steps;
        if (snap.shots == 7) during.request_stop();  // from the step, as a server thread would
        return true;
      },
      during.get_token());
  EXPECT_EQ(partial.stats.shots, 7);
  EXPECT_EQ(steps, 7);
}

TEST(Solution, ExtremeTiltsStayFiniteAndNonNegative) {
  // Slopes far beyond the outer ring, and normals tipped below the tangent plane.
  for (TextureMode mode : {TextureMode::Gather, TextureMode::Shoot}) {
    Scene s = bumpy_scene(mode);
    for (BumpFunction& b : s.bumps) b.amplitude = 10;
    Image img = render(s, solve(s));
    for (float v : img.rgb) ASSERT_TRUE(std::isfinite(v) && v >= 0) << int(mode);
  }
}

TEST(Solution, FlatBumpsRenderAsNoBumps) {
  for (TextureMode mode : {TextureMode::Gather, TextureMode::Shoot}) {
    Scene flat = bumpy_scene(mode);
    for (BumpFunction& b : flat.bumps) b.amplitude = 0;
    Scene plain = flat;
    plain.solver.texture = TextureMode::None;
    Solution s = solve(flat);
    ASSERT_TRUE(s.map);
    EXPECT_EQ(s.stats.map_values, 18u);
    EXPECT_GT(s.stats.perturbed_elements, 0u);
    // The same up to single precision, in which the view pass keeps a bumpy point's light.
    const Image a = render(flat, s), b = render(plain, solve(plain));
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    for (std::size_t i = 0; i < a.rgb.size(); ++i)
      ASSERT_NEAR(a.rgb[i], b.rgb[i], 1e-5 * std::max(b.rgb[i], 1e-3f))
          << "mode " << int(mode) << ", value " << i;
  }
}

// The heights of a normal-map test: 4 x 4 bumps h = (1 + sin 8 pi u sin 8 pi v) / 2, and their
// slopes.
double bump_height(double u, double v) {
  return 0.5 + 0.5 * std::sin(8 * std::numbers::pi * u) * std::sin(8 * std::numbers::pi * v);
}
glm::dvec2 bump_slope(double u, double v) {
  return {0.5 * 8 * std::numbers::pi * std::cos(8 * std::numbers::pi * u) *
              std::sin(8 * std::numbers::pi * v),
          0.5 * 8 * std::numbers::pi * std::sin(8 * std::numbers::pi * u) *
              std::cos(8 * std::numbers::pi * v)};
}

TEST(Solution, ANormalMapRendersLikeTheHeightsItWasComputedFrom) {
  // The floor (4 x 4: |P_u| = |P_v| = 4) with heights 0.1 h as an image bump, then with the
  // normal map of the same heights: by eq. (Blinn) on a plane, the tangent-space normal
  // (-0.1 h_u / 4, +0.1 h_v / 4, 1) (+y toward decreasing v). Tilts reach 17 degrees.
  constexpr int kSide = 256;
  auto heights = std::make_shared<Image>(kSide, kSide);
  auto normals = std::make_shared<Image>(kSide, kSide);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const double u = (x + 0.5) / kSide, v = (y + 0.5) / kSide;
      heights->set(x, y, Rgb(bump_height(u, v)));
      const glm::dvec2 slope = 0.1 * bump_slope(u, v) / 4.0;
      const Vec3 n = glm::normalize(Vec3(-slope.x, slope.y, 1));
      normals->set(x, y, (n + 1.0) / 2.0);
    }
  Scene with_heights = bumpy_scene(TextureMode::Gather);
  with_heights.objects[1].bump = 0;  // the floor
  with_heights.objects[2].bump = with_heights.objects[3].bump = -1;
  BumpFunction h;
  h.type = BumpType::Image;
  h.image = heights;
  h.amplitude = 0.1;
  with_heights.bumps = {h};
  Scene with_normals = with_heights;
  BumpFunction n;
  n.type = BumpType::NormalMap;
  n.image = normals;
  with_normals.bumps = {n};
  Scene flat = with_heights;
  flat.bumps[0].amplitude = 0;

  const Solution solved = solve(with_heights);
  const Image a = render(with_heights, solved), b = render(with_normals, solved);
  double diff = 0, sum = 0, bumps = 0;
  const Image plain = render(flat, solved);
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    diff += std::pow(double(b.rgb[i]) - a.rgb[i], 2);
    bumps += std::pow(double(plain.rgb[i]) - a.rgb[i], 2);
    sum += std::pow(double(a.rgb[i]), 2);
  }
  EXPECT_LT(std::sqrt(diff / sum), 0.01);  // the bound: within 1 %
  EXPECT_GT(std::sqrt(bumps / sum), 0.05) << "the bumps show";
}

}  // namespace
}  // namespace bumprad
