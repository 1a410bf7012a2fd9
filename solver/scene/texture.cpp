#include "solver/scene/texture.h"

#include <algorithm>
#include <cmath>

#include "solver/scene/geometry.h"

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

Rgb emission_at(const Material& m, glm::dvec2 uv) {
  return m.emission_texture ? m.emission * texture_reflectance(*m.emission_texture, uv)
                            : m.emission;
}

Rgb texture_mean(const ColorTexture& t) {
  if (t.kind == ColorTexture::Kind::Checker) return (t.colors[0] + t.colors[1]) / 2.0;
  return image_mean(*t.image);
}

std::vector<Rgb> element_reflectance(const Mesh& mesh, std::span<const Material> materials) {
  std::vector<Rgb> rho(mesh.elements.size());
  constexpr int kN = 8;
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    const Material& m = materials[std::size_t(e.material)];
    if (!m.texture) {
      rho[i] = m.reflectance;
      continue;
    }
    Rgb sum(0);
    for (int a = 0; a < kN; ++a)
      for (int b = 0; b < kN; ++b) {
        double u = (a + 0.5) / kN, v = (b + 0.5) / kN;
        if (e.vertex_count == 3 && u + v > 1) u = 1 - u, v = 1 - v;  // folded onto the triangle
        sum += texture_reflectance(*m.texture, surface_at(mesh, e, u, v).uv);
      }
    rho[i] = sum / double(kN * kN);
  }
  return rho;
}

}  // namespace bumprad
