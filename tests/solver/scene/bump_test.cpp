// Bump functions' derivatives and Blinn's perturbed normal.
#include "solver/scene/bump.h"

#include <memory>

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

namespace bumprad {
namespace {

TEST(Bump, DerivativesMatchCentralDifferencesOfTheHeight) {
  for (BumpType type : {BumpType::Noise, BumpType::Wrinkles, BumpType::Bricks, BumpType::Tiles,
                        BumpType::Dimples, BumpType::Cylinder}) {
    BumpFunction b;
    b.type = type;
    b.amplitude = 0.02;
    b.scale = {3, 5};
    b.direction_deg = 30;
    for (glm::dvec2 uv : {glm::dvec2(0.123, 0.456), glm::dvec2(0.71, 0.29), glm::dvec2(0.5, 0.9)}) {
      const double h = 1e-6;
      BumpSample s = evaluate_bump(b, uv);
      double du = (evaluate_bump(b, uv + glm::dvec2(h, 0)).height -
                   evaluate_bump(b, uv - glm::dvec2(h, 0)).height) /
                  (2 * h);
      double dv = (evaluate_bump(b, uv + glm::dvec2(0, h)).height -
                   evaluate_bump(b, uv - glm::dvec2(0, h)).height) /
                  (2 * h);
      EXPECT_NEAR(s.du, du, 1e-3 * (1 + std::abs(du))) << int(type);
      EXPECT_NEAR(s.dv, dv, 1e-3 * (1 + std::abs(dv))) << int(type);
    }
  }
}

TEST(Bump, ImageHeightMapSlopesFollowTheImage) {
  // A 16 x 16 ramp rising along u: heights x / 15 in the red, green and blue channels.
  auto img = std::make_shared<Image>(16, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) img->set(x, y, Rgb(x / 15.0));
  BumpFunction b;
  b.type = BumpType::Image;
  b.image = img;
  b.wrap = Wrap::Clamp;
  b.amplitude = 0.1;
  BumpSample s = evaluate_bump(b, {0.5, 0.5});
  // One texel (1/16 of u) rises 1/15 of the amplitude.
  EXPECT_NEAR(s.du, 0.1 * 16 / 15.0, 1e-6);  // texels are floats
  EXPECT_NEAR(s.dv, 0, 1e-12);
  EXPECT_NEAR(s.height, 0.1 * 7.5 / 15, 1e-6);
}

TEST(Bump, BlinnTiltOnAPlaneIsTheSlope) {
  // P(u,v) = (2u, 3v, 0): F = 0.5 u tilts N by atan(0.5 / 2) away from +x.
  Vec3 n = perturb_normal(Vec3(0, 0, 1), Vec3(2, 0, 0), Vec3(0, 3, 0), 0.5, 0);
  EXPECT_NEAR(std::atan2(-n.x, n.z), std::atan(0.25), 1e-12);
  EXPECT_NEAR(n.y, 0, 1e-15);
  // Against a flipped normal the height rises toward -z: the surface mirrors in z, so its
  // normal keeps the x tilt and flips z.
  Vec3 f = perturb_normal(Vec3(0, 0, -1), Vec3(2, 0, 0), Vec3(0, 3, 0), 0.5, 0);
  EXPECT_NEAR(f.x, n.x, 1e-12);
  EXPECT_NEAR(f.z, -n.z, 1e-12);
}

TEST(Bump, ZeroSlopeLeavesTheNormalAlone) {
  Vec3 n = glm::normalize(Vec3(0.3, -0.2, 0.9));
  EXPECT_EQ(perturb_normal(n, Vec3(1, 0, 0.1), Vec3(0, 1, 0.3), 0, 0), n);
}

// A normal map of one colour everywhere.
BumpFunction uniform_normal_map(const Rgb& texel) {
  auto img = std::make_shared<Image>(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) img->set(x, y, texel);
  BumpFunction b;
  b.type = BumpType::NormalMap;
  b.image = img;
  return b;
}

TEST(Bump, NormalMapsTurnTheNormalInTheTangentFrame) {
  // P(u,v) = (2u, 3v, 0). The map's +x is along u; its +y is toward decreasing v (the top
  // of the image: OpenGL's and glTF's convention), whichever way the normal faces.
  const Vec3 pu(2, 0, 0), pv(0, 3, 0);
  const Vec3 flat =
      bumped_normal(uniform_normal_map(Rgb(0.5, 0.5, 1)), {0.3, 0.3}, Vec3(0, 0, 1), pu, pv);
  EXPECT_NEAR(glm::length(flat - Vec3(0, 0, 1)), 0, 1e-12);
  const Rgb tilted((0.6 + 1) / 2, (0.0 + 1) / 2, (0.8 + 1) / 2);  // (0.6, 0, 0.8)
  EXPECT_NEAR(
      glm::length(bumped_normal(uniform_normal_map(tilted), {0.3, 0.3}, Vec3(0, 0, 1), pu, pv) -
                  Vec3(0.6, 0, 0.8)),
      0, 1e-6);
  const Rgb up((0.0 + 1) / 2, (0.6 + 1) / 2, (0.8 + 1) / 2);
  EXPECT_NEAR(glm::length(bumped_normal(uniform_normal_map(up), {0.3, 0.3}, Vec3(0, 0, 1), pu, pv) -
                          Vec3(0, -0.6, 0.8)),
              0, 1e-6);
  EXPECT_NEAR(
      glm::length(bumped_normal(uniform_normal_map(up), {0.3, 0.3}, Vec3(0, 0, -1), pu, pv) -
                  Vec3(0, -0.6, -0.8)),
      0, 1e-6);
  // glTF's scale multiplies x and y before normalising.
  BumpFunction stronger = uniform_normal_map(tilted);
  stronger.strength = 2;
  EXPECT_NEAR(glm::length(bumped_normal(stronger, {0.3, 0.3}, Vec3(0, 0, 1), pu, pv) -
                          glm::normalize(Vec3(1.2, 0, 0.8))),
              0, 1e-6);
}

TEST(Bump, ANormalMapOfBlinnsNormalGivesBlinnsNormal) {
  // F = 0.5 u on P(u,v) = (2u, 3v, 0) tilts N to (-0.25, 0, 1) normalised: as a normal map,
  // the same normal; on a sheared tangent frame (P_v leaning along u) too, as the frame is
  // made orthonormal from P_u first.
  const Vec3 n = perturb_normal(Vec3(0, 0, 1), Vec3(2, 0, 0), Vec3(0, 3, 0), 0.5, 0);
  const BumpFunction map = uniform_normal_map((n + 1.0) / 2.0);
  EXPECT_NEAR(
      glm::length(bumped_normal(map, {0.5, 0.5}, Vec3(0, 0, 1), Vec3(2, 0, 0), Vec3(0, 3, 0)) - n),
      0, 1e-6);
  EXPECT_NEAR(
      glm::length(bumped_normal(map, {0.5, 0.5}, Vec3(0, 0, 1), Vec3(2, 0, 0), Vec3(1, 3, 0)) - n),
      0, 1e-6);
}

}  // namespace
}  // namespace bumprad
