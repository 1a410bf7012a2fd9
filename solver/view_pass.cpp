#include "solver/view_pass.h"

#include <algorithm>
#include <atomic>
#include <numbers>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>

#include "solver/bump.h"
#include "solver/camera.h"
#include "solver/texture.h"
#include "solver/vertex_radiosity.h"

namespace bumprad {

namespace {

// Radiosity at a bumpy point: N' from the bump function in the frame of the interpolated
// surface, then each corner's B + (B'(N') - B'(N)) from the map, interpolated.
Rgb bumpy_radiosity(const Mesh& mesh, const Element& e, const std::array<double, 4>& w,
                    const BumpFunction& bump, const PerturbedMap& map,
                    std::span<const Rgb> vertex) {
  glm::dvec2 uv(0);
  Vec3 n(0), dpdu(0), dpdv(0);
  for (int k = 0; k < e.vertex_count; ++k) {
    const Vertex& v = mesh.vertices[e.v[std::size_t(k)]];
    double wk = w[std::size_t(k)];
    uv += wk * v.uv;
    n += wk * v.normal;
    dpdu += wk * v.dpdu;
    dpdv += wk * v.dpdv;
  }
  n = glm::normalize(n);
  BumpSample f = evaluate_bump(bump, uv);
  Vec3 local = tangent_frame(n, dpdu).to_local(perturb_normal(n, dpdu, dpdv, f.du, f.dv));
  Rgb b(0);
  for (int k = 0; k < e.vertex_count; ++k) {
    std::uint32_t vi = e.v[std::size_t(k)];
    Rgb bk = vertex[vi];
    if (std::int32_t slot = map.slot(vi); slot >= 0)
      bk += map.lookup(std::uint32_t(slot), local) - map.samples(std::uint32_t(slot))[0];
    b += w[std::size_t(k)] * bk;
  }
  return glm::max(b, Rgb(0));
}

}  // namespace

Image render_view(const Mesh& mesh, const RayScene& rays, const Camera& camera,
                  std::span<const Rgb> element_radiosity, const SurfaceDetail& detail) {
  const std::vector<Rgb> vertex = vertex_radiosity(mesh, element_radiosity);
  const PinholeCamera pinhole(camera);
  const int n = std::max(1, camera.antialias);
  std::vector<Rgb> texture_scale(detail.materials.size(), Rgb(0));  // 1 / mean reflectance
  for (std::size_t m = 0; m < detail.materials.size(); ++m)
    if (const auto& t = detail.materials[m].texture) {
      Rgb mean = texture_mean(*t);
      for (int c = 0; c < 3; ++c) texture_scale[m][c] = mean[c] > 0 ? 1 / mean[c] : 0;
    }
  Image image(camera.width, camera.height);

  auto shade = [&](const Hit& hit) {
    const Element& e = mesh.elements[hit.element];
    std::array<double, 4> w = corner_weights(e, hit.u, hit.v);
    int bump = detail.map ? detail.object_bump[e.object] : -1;
    Rgb b = bump < 0
                ? interpolate(e, vertex, hit.u, hit.v)
                : bumpy_radiosity(mesh, e, w, detail.bumps[std::size_t(bump)], *detail.map, vertex);
    if (detail.materials.empty()) return b;
    const Material& m = detail.materials[std::size_t(e.material)];
    if (!m.texture) return b;
    glm::dvec2 uv(0);
    for (int k = 0; k < e.vertex_count; ++k)
      uv += w[std::size_t(k)] * mesh.vertices[e.v[std::size_t(k)]].uv;
    Rgb rho = texture_reflectance(*m.texture, uv) * texture_scale[std::size_t(e.material)];
    return m.emission + glm::max(b - m.emission, Rgb(0)) * rho;
  };

  std::atomic<int> next_row{0};
  auto work = [&] {
    for (int y; (y = next_row++) < camera.height;) {
      for (int x = 0; x < camera.width; ++x) {
        Rgb sum(0);
        for (int sy = 0; sy < n; ++sy)
          for (int sx = 0; sx < n; ++sx) {
            auto hit = rays.intersect(pinhole.ray(x + (sx + 0.5) / n, y + (sy + 0.5) / n));
            if (hit && hit->front) sum += shade(*hit);
          }
        image.set(x, y, sum / (double(n * n) * std::numbers::pi));
      }
    }
  };
  unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::jthread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  return image;
}

}  // namespace bumprad
