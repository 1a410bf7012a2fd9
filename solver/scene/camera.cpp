#include "solver/scene/camera.h"

#include <algorithm>
#include <array>
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

bool same_view(const Camera& a, const Camera& b) {
  return a.position == b.position && a.look_at == b.look_at && a.up == b.up &&
         a.fov_y_deg == b.fov_y_deg && a.width == b.width && a.height == b.height &&
         a.antialias == b.antialias && a.antialias_max == b.antialias_max &&
         a.max_depth == b.max_depth && a.glossy_samples == b.glossy_samples &&
         a.shadow_rays == b.shadow_rays;
}

int adaptive_antialias(const Camera& camera) {
  if (camera.antialias <= 1) return 0;
  return camera.antialias_max > 0 ? camera.antialias_max
                                  : std::min(2 * camera.antialias, Limits::kMaxAntialiasMax);
}

Camera framed_camera(const Mesh& mesh, Camera camera) {
  Vec3 lo(0), hi(0);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& p = mesh.vertices[i].position;
    lo = i ? glm::min(lo, p) : p;
    hi = i ? glm::max(hi, p) : p;
  }
  const Vec3 centre = (lo + hi) / 2.0, half = (hi - lo) / 2.0;
  double inward = 0;
  std::array<double, 6> wall{};  // area facing in near each side: +x, -x, +y, -y, +z, -z
  for (const Element& e : mesh.elements) {
    const Vec3 n = e.normal * e.area;
    const Vec3 at = e.centroid - centre;
    inward -= glm::dot(n, at);
    for (int k = 0; k < 6; ++k) {
      const int axis = k / 2;
      const double side = k % 2 ? -1 : 1;
      if (side * at[axis] > 0.9 * half[axis])
        wall[std::size_t(k)] += std::max(0.0, -side * n[axis]);
    }
  }
  const double fov = glm::radians(camera.fov_y_deg);
  camera.up = {0, 1, 0};
  if (!(inward > 0)) {
    const double radius = std::max(1e-9, glm::length(half));
    camera.look_at = centre;
    camera.position = centre + Vec3(0, 0, radius / std::sin(fov / 2));
    return camera;
  }
  std::size_t open = 4;  // +z unless another side has less wall
  for (std::size_t k : {4, 5, 0, 1, 2, 3})
    if (wall[k] < wall[open] * (1 - 1e-9)) open = k;
  const int axis = int(open / 2);
  Vec3 d(0);
  d[axis] = open % 2 ? -1 : 1;
  // An open side (next to no wall there): from outside it, the room's cross-section filling
  // the view, as the Cornell box's own camera stands. A closed room: from just inside a wall.
  double across = 0, walls = 0;
  for (int c = 0; c < 3; ++c)
    if (c != axis) across = std::max(across, half[c]);
  for (double w : wall) walls += w / 6;
  const bool outside = wall[open] < 0.01 * walls;
  camera.position =
      centre + d * (outside ? half[axis] + across / std::tan(fov / 2) : 0.95 * half[axis]);
  camera.look_at = centre;
  if (axis == 1) camera.up = {0, 0, 1};
  return camera;
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
