#include "solver/render/error_estimate.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <glm/geometric.hpp>

#include "common/stopwatch.h"
#include "solver/scene/camera.h"
#include "solver/scene/geometry.h"
#include "solver/util/parallel.h"
#include "solver/util/random.h"

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
    ray = {point + e.normal * ray_epsilon(mesh), glm::reflect(ray.direction, e.normal)};
  }
  return false;
}

}  // namespace

std::vector<bool> emitter_pixels(const Scene& scene, const Mesh& mesh, const RayScene& rays) {
  const Camera& c = scene.camera;
  const PinholeCamera pinhole(c);
  // Bytes, not std::vector<bool>: rows are written from several threads.
  std::vector<char> light(std::size_t(c.width) * std::size_t(c.height), 0);
  parallel_for(c.height, [&](int y) {
    for (int x = 0; x < c.width; ++x)
      // 8 x 8 rays a pixel: a light seen edge-on covers slivers of pixels.
      for (int k = 0; k < 64; ++k)
        if (sees_emitter(scene, mesh, rays,
                         pinhole.ray(x + (k % 8 + 0.5) / 8, y + (k / 8 + 0.5) / 8))) {
          light[std::size_t(y) * std::size_t(c.width) + std::size_t(x)] = 1;
          break;
        }
  });
  std::vector<bool> near(light.begin(), light.end());
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

ErrorEstimator::ErrorEstimator(const Scene& scene, const Mesh& mesh, const RayScene& rays,
                               const ErrorEstimateSettings& settings)
    : view_(scene) {
  auto t0 = Clock::now();
  Camera& c = view_.camera;
  const double scale =
      std::min({1.0, double(settings.max_height) / c.height, 2.0 * settings.max_height / c.width});
  c.width = std::max(1, int(std::lround(c.width * scale)));
  c.height = std::max(1, int(std::lround(c.height * scale)));
  const std::vector<bool> emitter = emitter_pixels(view_, mesh, rays);

  std::vector<PixelIndex> lit;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      if (!emitter[std::size_t(y) * std::size_t(c.width) + std::size_t(x)]) lit.push_back({x, y});
  Random random(hash64(settings.seed));
  shuffle(std::span(lit), random);
  lit.resize(std::min(lit.size(), std::size_t(std::max(1, settings.pixels))));
  traced_ = trace_pixels(view_, mesh, rays, lit, {settings.paths, settings.seed + 1});
  trace_seconds_ = seconds_since(t0);
}

ErrorEstimate ErrorEstimator::estimate(const Image& image) const {
  auto t0 = Clock::now();
  // E|a - r'|^2 = |a - r|^2 + var(r') and E|r'|^2 = |r|^2 + var(r') for the traced r': per
  // pixel, x = |a - r'|^2 - var estimates the squared error and y = |r'|^2 - var the
  // squared norm, each without bias.
  const std::size_t n = traced_.size();
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    const TracedPixel& t = traced_[i];
    const Rgb d = image.at(t.pixel.x, t.pixel.y) - t.radiance;
    x[i] = glm::dot(d, d) - t.variance;
    y[i] = glm::dot(t.radiance, t.radiance) - t.variance;
  }
  const double sx = std::accumulate(x.begin(), x.end(), 0.0),
               sy = std::max(1e-300, std::accumulate(y.begin(), y.end(), 0.0));
  const double squared = std::max(0.0, sx) / sy;
  // The ratio's variance, linearised: that of the mean of z = x - squared y over the sample.
  // Each pixel's x carries its traced noise, so this counts both the draw of pixels and the
  // path tracer's noise (and so takes no finite-population correction: a view traced whole
  // still has the latter).
  double mean = 0, spread = 0;
  for (std::size_t i = 0; i < n; ++i) mean += (x[i] - squared * y[i]) / double(n);
  for (std::size_t i = 0; i < n; ++i) spread += std::pow(x[i] - squared * y[i] - mean, 2);
  const double var_mean = n > 1 ? spread / double(n - 1) / double(n) : 0;
  const double sd = double(n) * std::sqrt(var_mean) / sy;  // of `squared`
  ErrorEstimate e;
  e.pixels = int(n);
  e.relative_rms = std::sqrt(squared);
  e.standard_error = 0.5 * (std::sqrt(squared + sd) - std::sqrt(std::max(0.0, squared - sd)));
  e.seconds = trace_seconds_ + seconds_since(t0);
  return e;
}

}  // namespace bumprad
