#include "bench/truth_metrics.h"

#include <algorithm>
#include <cmath>

#include "solver/scene/camera.h"

namespace bumprad {

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

Image difference_image(const Image& a, const Image& r, const std::vector<bool>& emitter) {
  auto mean_luminance = [](const Image& im, int x, int y) {
    double sum = 0;
    int n = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int sx = x + dx, sy = y + dy;
        if (sx < 0 || sy < 0 || sx >= im.width || sy >= im.height) continue;
        const Rgb c = im.at(sx, sy);
        sum += c.r + c.g + c.b;
        ++n;
      }
    return sum / n;
  };
  Image out(r.width, r.height);
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) {
      if (emitter[std::size_t(y) * std::size_t(r.width) + std::size_t(x)]) continue;
      const double ref = mean_luminance(r, x, y);
      if (!(ref > 0)) continue;
      const double off = std::clamp((mean_luminance(a, x, y) / ref - 1) / 0.2, -1.0, 1.0);
      // PNG encoding applies the sRGB curve: undo it, so that the shade is linear in `off`.
      const double shade = std::pow(std::abs(off), 2.2);
      out.set(x, y, off > 0 ? Rgb(shade, 0, 0) : Rgb(0, 0, shade));
    }
  return out;
}

std::vector<int> pixel_objects(const Scene& scene, const Mesh& mesh, const RayScene& rays) {
  const Camera& c = scene.camera;
  const PinholeCamera pinhole(c);
  std::vector<int> out(std::size_t(c.width) * std::size_t(c.height), -1);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      if (const auto hit = rays.intersect(pinhole.ray(x + 0.5, y + 0.5)))
        out[std::size_t(y) * std::size_t(c.width) + std::size_t(x)] =
            int(mesh.elements[hit->element].object);
  return out;
}

double speckle(const Image& a, const Image& b, const std::vector<int>& objects, int object) {
  auto difference = [&](int x, int y) {
    const Rgb c = a.at(x, y) - b.at(x, y);
    return c.r + c.g + c.b;
  };
  double squares = 0, sum = 0;
  int count = 0;
  for (int y = 2; y + 2 < a.height; ++y)
    for (int x = 2; x + 2 < a.width; ++x) {
      double mean = 0;
      bool inside = true;
      for (int dy = -2; dy <= 2 && inside; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          inside &=
              objects[std::size_t(y + dy) * std::size_t(a.width) + std::size_t(x + dx)] == object;
          mean += difference(x + dx, y + dy) / 25;
        }
      if (!inside) continue;
      const double high = difference(x, y) - mean;
      const Rgb c = b.at(x, y);
      squares += high * high;
      sum += c.r + c.g + c.b;
      ++count;
    }
  return count > 0 && sum > 0 ? std::sqrt(squares / count) / (sum / count) : 0;
}

double without_noise(double measured, double noise) {
  return std::sqrt(std::max(0.0, measured * measured - noise * noise));
}

}  // namespace bumprad
