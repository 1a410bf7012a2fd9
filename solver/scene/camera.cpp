#include "solver/scene/camera.h"

#include <algorithm>

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace bumprad {

Camera draft_camera(Camera camera) {
  camera.antialias = 1;
  camera.glossy_samples = std::min(camera.glossy_samples, 2);
  camera.shadow_rays = 1;
  return camera;
}

int adaptive_antialias(const Camera& camera) {
  if (camera.antialias <= 1) return 0;
  return camera.antialias_max > 0 ? camera.antialias_max
                                  : std::min(2 * camera.antialias, Limits::kMaxAntialiasMax);
}

PinholeCamera::PinholeCamera(const Camera& c)
    : position_(c.position),
      forward_(glm::normalize(c.look_at - c.position)),
      right_(glm::normalize(glm::cross(forward_, c.up))),
      up_(glm::cross(right_, forward_)),
      half_height_(std::tan(glm::radians(c.fov_y_deg) / 2)),
      half_width_(half_height_ * c.width / c.height),
      width_(c.width),
      height_(c.height) {}

Ray PinholeCamera::ray(double x, double y) const {
  double sx = (2 * x / width_ - 1) * half_width_;
  double sy = (1 - 2 * y / height_) * half_height_;
  return {position_, glm::normalize(forward_ + sx * right_ + sy * up_)};
}

}  // namespace bumprad
