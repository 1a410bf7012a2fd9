#include "solver/radiosity/vertex_radiosity.h"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "solver/scene/geometry.h"
#include "solver/util/frame.h"
#include "solver/util/parallel.h"

namespace bumprad {

std::vector<Rgb> vertex_radiosity(const Mesh& mesh, std::span<const Rgb> element_radiosity,
                                  std::span<const double> open) {
  // Open area first; a vertex among buried elements only takes their plain mean.
  std::vector<Rgb> sum(mesh.vertices.size(), Rgb(0)), buried(mesh.vertices.size(), Rgb(0));
  std::vector<double> area(mesh.vertices.size(), 0.0), buried_area(mesh.vertices.size(), 0.0);
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    const double w = open.empty() ? e.area : e.area * open[i];
    for (int k = 0; k < e.vertex_count; ++k) {
      sum[e.v[k]] += element_radiosity[i] * w;
      area[e.v[k]] += w;
      buried[e.v[k]] += element_radiosity[i] * e.area;
      buried_area[e.v[k]] += e.area;
    }
  }
  for (std::size_t v = 0; v < sum.size(); ++v)
    if (area[v] > 0)
      sum[v] /= area[v];
    else if (buried_area[v] > 0)
      sum[v] = buried[v] / buried_area[v];
  return sum;
}

std::vector<double> open_share(const Mesh& mesh, const RayScene& rays, std::stop_token stop) {
  const double epsilon = ray_epsilon(mesh);
  // A point on a non-planar quad may lie a little behind the two triangles Embree makes of
  // it: a ray that meets its own element first passes on from there.
  auto first_hit = [&](std::uint32_t self, Ray ray) {
    auto hit = rays.intersect(ray);
    if (hit && hit->element == self) {
      ray.origin += ray.direction * (hit->t + epsilon);
      hit = rays.intersect(ray);
    }
    return hit;
  };
  auto is_open = [&](std::uint32_t i, const Vec3& point) {
    const Element& e = mesh.elements[i];
    const Frame frame = frame_about(e.normal);
    const Vec3 from = point + e.normal * epsilon;
    for (int d = 0; d < 5; ++d) {
      const double phi = std::numbers::pi / 2 * d;
      const Vec3 local =
          d == 0 ? Vec3(0, 0, 1) : Vec3(0.866 * std::cos(phi), 0.866 * std::sin(phi), 0.5);
      auto hit = first_hit(i, {from, frame.to_world(local)});
      if (!hit || hit->front) return true;
    }
    return false;
  };
  std::vector<double> out(mesh.elements.size(), 1.0);
  parallel_for(
      int(mesh.elements.size()),
      [&](int index) {
        const std::size_t i = std::size_t(index);
        const Element& e = mesh.elements[i];
        int open = 0;
        for (const Vec3& point : quarter_points(mesh, e)) open += is_open(std::uint32_t(i), point);
        if (open == 0 || open == 4) {
          out[i] = open / 4.0;
          return;
        }
        // Partly buried: the share divides the element's radiosity (view_pass.cpp), so measure
        // it on a finer 8 x 8 grid (triangles: the points that fall inside).
        int inside = 0;
        open = 0;
        for (int a = 0; a < 8; ++a)
          for (int b = 0; b < 8; ++b) {
            const double u = (a + 0.5) / 8, v = (b + 0.5) / 8;
            if (e.vertex_count == 3 && u + v > 1) continue;
            std::array<double, 4> w = corner_weights(e, u, v);
            Vec3 point(0);
            for (int k = 0; k < e.vertex_count; ++k)
              point += w[std::size_t(k)] * mesh.vertices[e.v[std::size_t(k)]].position;
            ++inside;
            open += is_open(std::uint32_t(i), point);
          }
        out[i] = std::max(1, open) / double(inside);
      },
      stop);
  return out;
}

Rgb interpolate(const Element& e, std::span<const Rgb> values, double u, double v) {
  auto w = corner_weights(e, u, v);
  Rgb sum(0);
  for (int k = 0; k < e.vertex_count; ++k) sum += w[std::size_t(k)] * values[e.v[std::size_t(k)]];
  return sum;
}

}  // namespace bumprad
