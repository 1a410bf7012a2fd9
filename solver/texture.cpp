#include "solver/texture.h"

#include <algorithm>
#include <cmath>

namespace bumprad {
namespace {

// Maps a texel index into [0, n) by the wrap mode.
int wrap_index(int i, int n, Wrap wrap) {
  switch (wrap) {
    case Wrap::Clamp:
      return std::clamp(i, 0, n - 1);
    case Wrap::Mirror: {
      int period = 2 * n, m = ((i % period) + period) % period;
      return m < n ? m : period - 1 - m;
    }
    case Wrap::Repeat:
      break;
  }
  return ((i % n) + n) % n;
}

}  // namespace

Rgb sample_image(const Image& image, glm::dvec2 p, Wrap wrap) {
  double x = p.x * image.width - 0.5, y = p.y * image.height - 0.5;
  int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  double fx = x - x0, fy = y - y0;
  auto at = [&](int i, int j) {
    return image.at(wrap_index(i, image.width, wrap), wrap_index(j, image.height, wrap));
  };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
         fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

Rgb texture_reflectance(const ColorTexture& t, glm::dvec2 uv) {
  glm::dvec2 p = uv * t.scale + t.offset;
  if (t.kind == ColorTexture::Kind::Image) return sample_image(*t.image, p, t.wrap);
  int parity = (int(std::floor(p.x)) + int(std::floor(p.y))) & 1;
  return t.colors[std::size_t(parity)];
}

Rgb texture_mean(const ColorTexture& t) {
  if (t.kind == ColorTexture::Kind::Checker) return (t.colors[0] + t.colors[1]) / 2.0;
  Rgb sum(0);
  for (int y = 0; y < t.image->height; ++y)
    for (int x = 0; x < t.image->width; ++x) sum += t.image->at(x, y);
  return sum / double(t.image->width * t.image->height);
}

}  // namespace bumprad
