#include "solver/scene/subdivision.h"
#include "solver/scene/geometry.h"

#include <algorithm>
#include <map>

#include <glm/geometric.hpp>

namespace bumprad {
namespace {

double luminance(const Rgb& c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

Vec3 unit_or(const Vec3& v, const Vec3& fallback) {
  double len = glm::length(v);
  return len > 0 ? v / len : fallback;
}

// Adds vertices between existing ones, once per edge.
class VertexMaker {
 public:
  explicit VertexMaker(std::vector<Vertex>& vertices) : vertices_(vertices) {}

  std::uint32_t between(std::uint32_t a, std::uint32_t b) {
    auto key = std::minmax(a, b);
    auto [it, inserted] = edges_.try_emplace({key.first, key.second}, 0);
    if (inserted) it->second = mean({a, b});
    return it->second;
  }

  std::uint32_t mean(std::initializer_list<std::uint32_t> ids) {
    Vertex v{Vec3(0), Vec3(0), glm::dvec2(0), Vec3(0), Vec3(0)};
    const double w = 1.0 / double(ids.size());
    for (std::uint32_t id : ids) {
      const Vertex& s = vertices_[id];
      v.position += w * s.position;
      v.normal += s.normal;
      v.uv += w * s.uv;
      v.dpdu += w * s.dpdu;
      v.dpdv += w * s.dpdv;
    }
    v.normal = unit_or(v.normal, vertices_[*ids.begin()].normal);
    vertices_.push_back(v);
    return std::uint32_t(vertices_.size() - 1);
  }

 private:
  std::vector<Vertex>& vertices_;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edges_;
};

}  // namespace

std::vector<std::uint32_t> elements_to_split(const Mesh& mesh, std::span<const Rgb> radiosity,
                                             double threshold) {
  double mean = 0, area = 0;
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    mean += luminance(radiosity[i]) * mesh.elements[i].area;
    area += mesh.elements[i].area;
  }
  const double floor = area > 0 ? 0.01 * mean / area : 0;
  std::vector<std::vector<std::uint32_t>> around(mesh.vertices.size());
  for (std::uint32_t i = 0; i < mesh.elements.size(); ++i)
    for (int k = 0; k < mesh.elements[i].vertex_count; ++k)
      around[mesh.elements[i].v[std::size_t(k)]].push_back(i);
  std::vector<bool> marked(mesh.elements.size(), false);
  for (const auto& elements : around)
    for (std::size_t a = 0; a < elements.size(); ++a)
      for (std::size_t b = a + 1; b < elements.size(); ++b) {
        double ya = luminance(radiosity[elements[a]]), yb = luminance(radiosity[elements[b]]);
        if (std::abs(ya - yb) > threshold * std::max({ya, yb, floor}))
          marked[elements[a]] = marked[elements[b]] = true;
      }
  std::vector<std::uint32_t> out;
  for (std::uint32_t i = 0; i < marked.size(); ++i)
    if (marked[i]) out.push_back(i);
  return out;
}

Mesh subdivide(const Mesh& mesh, std::span<const std::uint32_t> split) {
  std::vector<bool> splitting(mesh.elements.size(), false);
  for (std::uint32_t i : split) splitting[i] = true;
  Mesh out;
  out.vertices = mesh.vertices;
  out.surface_count = mesh.surface_count;
  out.bounds_min = mesh.bounds_min;
  out.bounds_max = mesh.bounds_max;
  VertexMaker make(out.vertices);
  for (const Patch& p : mesh.patches) {
    Patch q = p;
    q.first = std::uint32_t(out.elements.size());
    for (std::uint32_t i = p.first; i < p.first + p.count; ++i) {
      const Element& e = mesh.elements[i];
      if (!splitting[i]) {
        out.elements.push_back(e);
        continue;
      }
      const auto& v = e.v;
      std::vector<std::array<std::uint32_t, 4>> children;
      if (e.vertex_count == 4) {
        std::uint32_t m01 = make.between(v[0], v[1]), m12 = make.between(v[1], v[2]),
                      m23 = make.between(v[2], v[3]), m30 = make.between(v[3], v[0]),
                      c = make.mean({v[0], v[1], v[2], v[3]});
        children = {
            {v[0], m01, c, m30}, {m01, v[1], m12, c}, {c, m12, v[2], m23}, {m30, c, m23, v[3]}};
      } else {
        std::uint32_t m01 = make.between(v[0], v[1]), m12 = make.between(v[1], v[2]),
                      m20 = make.between(v[2], v[0]);
        children = {
            {v[0], m01, m20, 0}, {m01, v[1], m12, 0}, {m20, m12, v[2], 0}, {m01, m12, m20, 0}};
      }
      for (const auto& corners : children) {
        Element child = e;
        child.v = corners;
        if (compute_element_geometry(out.vertices, child)) out.elements.push_back(child);
      }
    }
    q.count = std::uint32_t(out.elements.size()) - q.first;
    out.patches.push_back(q);
  }
  // Children stand where their parents stood, so groups stay contiguous. A child of an
  // element alone in its group is alone in its own: splitting refines what receives.
  std::uint32_t first = 0;
  for (std::uint32_t i = 1; i <= out.elements.size(); ++i) {
    const std::uint32_t was = out.elements[first].group;
    if (i < out.elements.size() && out.elements[i].group == was && mesh.groups[was].count > 1)
      continue;
    out.groups.push_back(element_run(out.elements, first, i - first));
    for (std::uint32_t j = first; j < i; ++j)
      out.elements[j].group = std::uint32_t(out.groups.size() - 1);
    first = i;
  }
  return out;
}

}  // namespace bumprad
