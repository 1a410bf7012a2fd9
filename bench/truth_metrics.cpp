#include "bench/truth_metrics.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "solver/camera.h"

namespace bumprad {
namespace {

bool emits(const Rgb& e) {
  return e.r + e.g + e.b > 0;
}

// Whether the ray meets an emitter, straight or through perfect mirrors (an emitter's image
// in a mirror is as bright and as small as the emitter).
bool sees_emitter(const Scene& scene, const Mesh& mesh, const RayScene& rays, Ray ray) {
  for (int bounce = 0; bounce < 4; ++bounce) {
    const auto hit = rays.intersect(ray);
    if (!hit || !hit->front) return false;
    const Element& e = mesh.elements[hit->element];
    const Material& m = scene.materials[std::size_t(e.material)];
    if (emits(m.emission)) return true;
    if (m.specular <= 0 || m.shininess > 0) return false;
    const Vec3 point = ray.origin + hit->t * ray.direction;
    ray = {point + e.normal * (1e-4 * mesh.diagonal()), glm::reflect(ray.direction, e.normal)};
  }
  return false;
}

}  // namespace

std::vector<bool> emitter_pixels(const Scene& scene, const Mesh& mesh, const RayScene& rays) {
  const Camera& c = scene.camera;
  const PinholeCamera pinhole(c);
  std::vector<bool> light(std::size_t(c.width) * std::size_t(c.height), false);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      // 8 x 8 rays a pixel: a light seen edge-on covers slivers of pixels.
      for (int k = 0; k < 64; ++k)
        if (sees_emitter(scene, mesh, rays,
                         pinhole.ray(x + (k % 8 + 0.5) / 8, y + (k / 8 + 0.5) / 8))) {
          light[std::size_t(y) * std::size_t(c.width) + std::size_t(x)] = true;
          break;
        }
  std::vector<bool> near = light;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int sx = x + dx, sy = y + dy;
          if (sx >= 0 && sy >= 0 && sx < c.width && sy < c.height &&
              light[std::size_t(sy) * std::size_t(c.width) + std::size_t(sx)])
            near[std::size_t(y) * std::size_t(c.width) + std::size_t(x)] = true;
        }
  return near;
}

Comparison compare(const Image& a, const Image& r, const std::vector<bool>& emitter) {
  double diff[2] = {0, 0}, norm[2] = {0, 0}, sa = 0, sr = 0;
  for (std::size_t i = 0; i < r.rgb.size(); ++i) {
    const double d = double(a.rgb[i]) - double(r.rgb[i]);
    const bool surface = !emitter[i / 3];
    for (int k = 0; k < 2; ++k)
      if (k == 0 || surface) {
        diff[k] += d * d;
        norm[k] += double(r.rgb[i]) * double(r.rgb[i]);
      }
    if (surface) sa += a.rgb[i], sr += r.rgb[i];
  }
  return {std::sqrt(diff[1] / norm[1]), std::sqrt(diff[0] / norm[0]), sa / sr};
}

double without_noise(double measured, double noise) {
  return std::sqrt(std::max(0.0, measured * measured - noise * noise));
}

}  // namespace bumprad
