// The pinhole camera's rays against its geometry: the image centre looks at look_at, the
// edges of the image sit at half the field of view, rows run down and columns right.
#include "solver/scene/camera.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

namespace bumprad {
namespace {

Camera camera() {
  Camera c;
  c.position = {1, 2, 3};
  c.look_at = {1, 2, 13};  // along +z
  c.up = {0, 1, 0};
  c.fov_y_deg = 60;
  c.width = 200;
  c.height = 100;
  return c;
}

double degrees_between(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * 180 / std::numbers::pi;
}

TEST(Camera, TheCentreLooksAtTheTargetAndTheEdgesAtHalfTheFieldOfView) {
  const PinholeCamera pinhole(camera());
  const Ray centre = pinhole.ray(100, 50);
  EXPECT_EQ(centre.origin, Vec3(1, 2, 3));
  EXPECT_NEAR(glm::length(centre.direction - Vec3(0, 0, 1)), 0, 1e-12);
  EXPECT_NEAR(glm::length(pinhole.ray(37, 81).direction), 1, 1e-12);
  // Top and bottom edges: 30 degrees up and down; the sides by the aspect (tan 30 x 2).
  const Ray top = pinhole.ray(100, 0), bottom = pinhole.ray(100, 100);
  EXPECT_NEAR(degrees_between(top.direction, centre.direction), 30, 1e-9);
  EXPECT_GT(top.direction.y, 0);
  EXPECT_LT(bottom.direction.y, 0);
  const double side = std::atan(2 * std::tan(std::numbers::pi / 6)) * 180 / std::numbers::pi;
  const Ray left = pinhole.ray(0, 50), right = pinhole.ray(200, 50);
  EXPECT_NEAR(degrees_between(left.direction, centre.direction), side, 1e-9);
  EXPECT_NEAR(degrees_between(right.direction, centre.direction), side, 1e-9);
  // Looking along +z with y up, "right" on the image is -x (a right-handed view).
  EXPECT_LT(right.direction.x * left.direction.x, 0);
}

TEST(Camera, DraftsTakeOneRayAPixelAndAdaptiveAntialiasingFollowsItsSettings) {
  Camera c = camera();
  c.antialias = 4;
  c.glossy_samples = 8;
  c.shadow_rays = 4;
  const Camera d = draft_camera(c);
  EXPECT_EQ(d.antialias, 1);
  EXPECT_EQ(d.glossy_samples, 2);
  EXPECT_EQ(d.shadow_rays, 1);
  EXPECT_EQ(d.width, c.width);
  EXPECT_EQ(d.exposure, c.exposure);
  EXPECT_EQ(adaptive_antialias(c), 8);  // 2n by default
  c.antialias_max = 6;
  EXPECT_EQ(adaptive_antialias(c), 6);
  c.antialias = 1;
  EXPECT_EQ(adaptive_antialias(c), 0);  // one ray gives no disagreement to see
}

}  // namespace
}  // namespace bumprad
