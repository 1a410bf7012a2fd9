#include "solver/scene/geometry.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "solver/util/frame.h"

namespace bumprad {

std::span<const Vec3> element_corners(const Mesh& mesh, const Element& e,
                                      std::array<Vec3, 4>& storage) {
  for (int k = 0; k < e.vertex_count; ++k)
    storage[std::size_t(k)] = mesh.vertices[e.v[std::size_t(k)]].position;
  return {storage.data(), std::size_t(e.vertex_count)};
}

bool compute_element_geometry(const std::vector<Vertex>& vertices, Element& e) {
  Vec3 sum_n(0), sum_c(0);
  double sum_a = 0;
  for (int t = 1; t + 1 < e.vertex_count; ++t) {
    Vec3 a = vertices[e.v[0]].position, b = vertices[e.v[t]].position,
         c = vertices[e.v[t + 1]].position;
    Vec3 n = glm::cross(b - a, c - a);
    double area = 0.5 * glm::length(n);
    sum_n += n;
    sum_c += area * (a + b + c) / 3.0;
    sum_a += area;
  }
  double len = glm::length(sum_n);
  if (!(sum_a > 0) || !(len > 0)) return false;
  e.area = sum_a;
  e.centroid = sum_c / sum_a;
  e.normal = sum_n / len;
  return true;
}

ElementRun element_run(std::span<const Element> elements, std::uint32_t first,
                       std::uint32_t count) {
  ElementRun r{first, count};
  for (std::uint32_t i = first; i < first + count; ++i) {
    const Element& e = elements[i];
    r.area += e.area;
    r.centroid += e.area * e.centroid;
    r.normal += e.area * e.normal;
  }
  if (r.area > 0) r.centroid /= r.area;
  const double len = glm::length(r.normal);
  if (len > 0) r.normal /= len;
  return r;
}

double run_radius(const Mesh& mesh, const ElementRun& run) {
  double radius = 0;
  for (std::uint32_t i = run.first; i < run.first + run.count; ++i) {
    const Element& e = mesh.elements[i];
    for (int k = 0; k < e.vertex_count; ++k)
      radius =
          std::max(radius, glm::length(mesh.vertices[e.v[std::size_t(k)]].position - run.centroid));
  }
  return radius;
}

std::array<double, 4> corner_weights(const Element& e, double u, double v) {
  if (e.vertex_count == 3) return {1 - u - v, u, v, 0};
  return {(1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v};
}

Vec3 point_at(const Mesh& mesh, const Element& e, double u, double v) {
  const std::array<double, 4> w = corner_weights(e, u, v);
  Vec3 point(0);
  for (int k = 0; k < e.vertex_count; ++k)
    point += w[std::size_t(k)] * mesh.vertices[e.v[std::size_t(k)]].position;
  return point;
}

std::vector<Vec3> part_points(const Mesh& mesh, const Element& e, int m) {
  std::vector<glm::dvec2> uv;
  if (e.vertex_count == 4) {
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) uv.push_back({(i + 0.5) / m, (j + 0.5) / m});
  } else {
    for (int j = 0; j < m; ++j)
      for (int i = 0; i + j < m; ++i) uv.push_back({(i + 1.0 / 3) / m, (j + 1.0 / 3) / m});
    for (int j = 0; j + 1 < m; ++j)
      for (int i = 0; i + j + 1 < m; ++i) uv.push_back({(i + 2.0 / 3) / m, (j + 2.0 / 3) / m});
  }
  std::vector<Vec3> out;
  for (const glm::dvec2& p : uv) out.push_back(point_at(mesh, e, p.x, p.y));
  return out;
}

std::array<Vec3, 4> quarter_points(const Mesh& mesh, const Element& e) {
  const std::vector<Vec3> p = part_points(mesh, e, 2);
  return {p[0], p[1], p[2], p[3]};
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

double ray_epsilon(const Mesh& mesh) {
  double extent = 0;
  for (int k = 0; k < 3; ++k)
    extent = std::max({extent, std::abs(mesh.bounds_min[k]), std::abs(mesh.bounds_max[k])});
  return 4e-6 * extent;
}

std::vector<Vec3> convex_hull(std::span<const Vec3> points, const Vec3& normal) {
  const Frame f = frame_about(normal);
  std::vector<Vec3> sorted(points.begin(), points.end());
  const auto local = [&](const Vec3& p) { return glm::dvec2(glm::dot(p, f.x), glm::dot(p, f.y)); };
  std::sort(sorted.begin(), sorted.end(), [&](const Vec3& a, const Vec3& b) {
    const glm::dvec2 la = local(a), lb = local(b);
    return la.x < lb.x || (la.x == lb.x && la.y < lb.y);
  });
  if (sorted.size() < 3) return sorted;
  const auto turn = [&](const Vec3& o, const Vec3& a, const Vec3& b) {
    const glm::dvec2 u = local(a) - local(o), v = local(b) - local(o);
    return u.x * v.y - u.y * v.x;
  };
  std::vector<Vec3> hull(2 * sorted.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < sorted.size(); ++i) {  // lower chain
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], sorted[i]) <= 0) --k;
    hull[k++] = sorted[i];
  }
  for (std::size_t i = sorted.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && turn(hull[k - 2], hull[k - 1], sorted[i]) <= 0) --k;
    hull[k++] = sorted[i];
  }
  hull.resize(k - 1);
  return hull;
}

bool degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double scale = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
  return !(glm::length(glm::cross(b - a, c - a)) > 1e-12 * scale * scale);
}

glm::dmat4 rotated_about_axes(const glm::dmat4& m, const Vec3& degrees) {
  glm::dmat4 r = glm::rotate(m, glm::radians(degrees.z), Vec3(0, 0, 1));
  r = glm::rotate(r, glm::radians(degrees.y), Vec3(0, 1, 0));
  return glm::rotate(r, glm::radians(degrees.x), Vec3(1, 0, 0));
}

double centroid_ray_offset(const Mesh& mesh) {
  return 1e-4 * mesh.diagonal();
}

double hemicube_lift(const Mesh& mesh) {
  return mesh.diagonal() * 1e-6;
}

bool coplanar(const Mesh& mesh, std::span<const std::uint32_t> elements, Flatness tolerance) {
  const Element& first = mesh.elements[elements.front()];
  const double offset = tolerance.offset * std::max(1.0, mesh.diagonal());
  for (std::uint32_t i : elements) {
    const Element& e = mesh.elements[i];
    if (glm::length(e.normal - first.normal) > tolerance.normal) return false;
    for (int k = 0; k < e.vertex_count; ++k)
      if (std::abs(glm::dot(mesh.vertices[e.v[std::size_t(k)]].position - first.centroid,
                            first.normal)) > offset)
        return false;
  }
  return true;
}

bool curved(const Mesh& mesh, const Patch& patch) {
  Vec3 facing(0);
  double area = 0;
  for (std::uint32_t k = patch.first; k < patch.first + patch.count; ++k) {
    facing += mesh.elements[k].area * mesh.elements[k].normal;
    area += mesh.elements[k].area;
  }
  return glm::length(facing) < 0.99 * area;
}

}  // namespace bumprad
