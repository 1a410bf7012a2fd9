#include "tests/test_scenes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "solver/scene/phong_lobe.h"
#include "solver/util/math.h"

namespace bumprad::test {

Object quad(const std::array<Vec3, 4>& corners, int nu, int nv, int material) {
  Object o;
  o.name = "quad";
  o.shape = QuadShape{corners};
  o.material = material;
  o.density.counts = {nu, nv};
  o.density.patch_elements = 1;
  return o;
}

std::array<Vec3, 4> rectangle_facing_down(double w, double h, double z) {
  return {Vec3(-w / 2, -h / 2, z), Vec3(-w / 2, h / 2, z), Vec3(w / 2, h / 2, z),
          Vec3(w / 2, -h / 2, z)};
}

TriangleMeshShape square_of_triangles(const Vec3& corner, int n, bool smooth) {
  TriangleMeshShape m;
  m.smooth = smooth;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.positions.push_back(corner + Vec3(double(i) / n, double(j) / n, 0));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = std::uint32_t(j * (n + 1) + i), c = a + std::uint32_t(n + 1);
      m.triangles.push_back({a, a + 1, c + 1});
      m.triangles.push_back({a, c + 1, c});
    }
  return m;
}

TriangleMeshShape hills(int n, double side, const std::function<double(double, double)>& height) {
  TriangleMeshShape m;
  m.smooth = true;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double u = double(i) / n, v = double(j) / n;
      m.positions.push_back(Vec3(side * u, height(u, v), side * v));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = std::uint32_t(j * (n + 1) + i), b = a + 1,
                          c = a + std::uint32_t(n + 1), d = c + 1;
      m.triangles.push_back({a, c, b});  // facing up
      m.triangles.push_back({b, c, d});
    }
  return m;
}

TriangleMeshShape ball(const Vec3& centre, double r, int rings) {
  TriangleMeshShape out;
  out.smooth = true;
  for (int j = 0; j <= rings; ++j)
    for (int i = 0; i <= 2 * rings; ++i) {
      const double theta = kPi * j / rings, phi = kPi * i / rings;
      out.positions.push_back(centre + r * Vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                                std::sin(theta) * std::sin(phi)));
    }
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < 2 * rings; ++i) {
      const std::uint32_t a = std::uint32_t(j * (2 * rings + 1) + i), b = a + 1,
                          c = a + std::uint32_t(2 * rings + 1), d = c + 1;
      out.triangles.push_back({a, b, c});  // facing out
      out.triangles.push_back({b, d, c});
    }
  return out;
}

Scene scene_of(std::vector<Object> objects, double rho, double emission) {
  Scene s;
  Material m;
  m.name = "grey";
  m.reflectance = Rgb(rho);
  m.emission = Rgb(emission);
  s.materials.push_back(m);
  s.objects = std::move(objects);
  return s;
}

Scene slab_across_a_closed_room(double rho, double emission) {
  const double w = 4, h = 4, slab = 1.4;
  const int n = 40;
  TriangleMeshShape top;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) top.positions.push_back(Vec3(w * i / n, slab, w * j / n));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = std::uint32_t(j * (n + 1) + i), c = a + std::uint32_t(n + 1);
      top.triangles.push_back({a, c + 1, a + 1});  // facing up
      top.triangles.push_back({a, c, c + 1});
    }
  Object ground;
  ground.shape = top;
  return scene_of({ground, quad({Vec3(0, h, 0), Vec3(w, h, 0), Vec3(w, h, w), Vec3(0, h, w)}, 8, 8),
                   quad({Vec3(0, h, w), Vec3(w, h, w), Vec3(w, 0, w), Vec3(0, 0, w)}, 8, 8),
                   quad({Vec3(0, 0, 0), Vec3(w, 0, 0), Vec3(w, h, 0), Vec3(0, h, 0)}, 8, 8),
                   quad({Vec3(0, h, 0), Vec3(0, h, w), Vec3(0, 0, w), Vec3(0, 0, 0)}, 8, 8),
                   quad({Vec3(w, 0, 0), Vec3(w, 0, w), Vec3(w, h, w), Vec3(w, h, 0)}, 8, 8),
                   quad({Vec3(0, 0, 0), Vec3(0, 0, w), Vec3(w, 0, w), Vec3(w, 0, 0)}, 8, 8)},
                  rho, emission);
}

Scene glossy_highlight() {
  Scene s = scene_of({quad({Vec3(-3, -3, 0), Vec3(3, -3, 0), Vec3(3, 3, 0), Vec3(-3, 3, 0)}),
                      quad(rectangle_facing_down(0.2, 0.2, 1), 1, 1, 1)},
                     0);
  for (Vec3& p : std::get<QuadShape>(s.objects[1].shape).corners) p.x += 1;
  s.materials[0].specular = 1;
  s.materials[0].shininess = 20;
  s.materials.push_back(emitter(50));
  s.camera.position = Vec3(-1, 0, 1);
  s.camera.look_at = Vec3(0);
  s.camera.up = Vec3(0, 0, 1);
  s.camera.fov_y_deg = 1;
  s.camera.width = s.camera.height = 8;
  return s;
}

double glossy_highlight_radiance(const Scene& scene) {
  const Vec3 eye = glm::normalize(scene.camera.look_at - scene.camera.position);
  const PhongLobe lobe(glm::reflect(eye, Vec3(0, 0, 1)), Vec3(0, 0, 1),
                       scene.materials[0].shininess);
  const auto& c = std::get<QuadShape>(scene.objects[1].shape).corners;
  const double area = glm::length(c[1] - c[0]) * glm::length(c[3] - c[0]);
  constexpr int kN = 64;
  double sum = 0;
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j) {
      const Vec3 y = c[0] + (c[1] - c[0]) * ((i + 0.5) / kN) + (c[3] - c[0]) * ((j + 0.5) / kN);
      const double r = glm::length(y);
      const Vec3 d = y / r;
      sum += lobe.pdf(d) * d.z / (r * r);  // the emitter faces -z: cos' = d.z
    }
  return scene.materials[1].emission.g / std::numbers::pi * sum * area / (kN * kN);
}

PixelSpread pixel_spread(const Image& image) {
  double sum = 0, square = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      sum += image.at(x, y).g;
      square += image.at(x, y).g * image.at(x, y).g;
    }
  const double n = image.width * image.height, mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, square / n - mean * mean)) / mean};
}

Material emitter(double emission) {
  Material m;
  m.reflectance = Rgb(0);
  m.emission = Rgb(emission);
  return m;
}

}  // namespace bumprad::test
