#include "solver/vertex_radiosity.h"

#include <glm/geometric.hpp>

namespace bumprad {

std::vector<Rgb> vertex_radiosity(const Mesh& mesh, std::span<const Rgb> element_radiosity) {
  std::vector<Rgb> sum(mesh.vertices.size(), Rgb(0));
  std::vector<double> area(mesh.vertices.size(), 0.0);
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    for (int k = 0; k < e.vertex_count; ++k) {
      sum[e.v[k]] += element_radiosity[i] * e.area;
      area[e.v[k]] += e.area;
    }
  }
  for (std::size_t v = 0; v < sum.size(); ++v)
    if (area[v] > 0) sum[v] /= area[v];
  return sum;
}

std::array<double, 4> corner_weights(const Element& e, double u, double v) {
  if (e.vertex_count == 3) return {1 - u - v, u, v, 0};
  return {(1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v};
}

Rgb interpolate(const Element& e, std::span<const Rgb> values, double u, double v) {
  auto w = corner_weights(e, u, v);
  Rgb sum(0);
  for (int k = 0; k < e.vertex_count; ++k) sum += w[std::size_t(k)] * values[e.v[std::size_t(k)]];
  return sum;
}

SurfaceAt surface_at(const Mesh& mesh, const Element& e, double u, double v) {
  SurfaceAt s{corner_weights(e, u, v), glm::dvec2(0), Vec3(0), Vec3(0), Vec3(0)};
  for (int k = 0; k < e.vertex_count; ++k) {
    const Vertex& vertex = mesh.vertices[e.v[std::size_t(k)]];
    const double w = s.weights[std::size_t(k)];
    s.uv += w * vertex.uv;
    s.normal += w * vertex.normal;
    s.dpdu += w * vertex.dpdu;
    s.dpdv += w * vertex.dpdv;
  }
  s.normal = glm::normalize(s.normal);
  return s;
}

}  // namespace bumprad
