#include "solver/view_pass.h"

#include <algorithm>
#include <atomic>
#include <numbers>
#include <thread>
#include <vector>

#include "solver/camera.h"
#include "solver/vertex_radiosity.h"

namespace bumprad {

Image render_view(const Mesh& mesh, const RayScene& rays, const Camera& camera,
                  std::span<const Rgb> element_radiosity) {
  const std::vector<Rgb> vertex = vertex_radiosity(mesh, element_radiosity);
  const PinholeCamera pinhole(camera);
  const int n = std::max(1, camera.antialias);
  Image image(camera.width, camera.height);

  std::atomic<int> next_row{0};
  auto work = [&] {
    for (int y; (y = next_row++) < camera.height;) {
      for (int x = 0; x < camera.width; ++x) {
        Rgb sum(0);
        for (int sy = 0; sy < n; ++sy)
          for (int sx = 0; sx < n; ++sx) {
            Ray ray = pinhole.ray(x + (sx + 0.5) / n, y + (sy + 0.5) / n);
            auto hit = rays.intersect(ray);
            if (!hit || !hit->front) continue;
            sum += interpolate(mesh.elements[hit->element], vertex, hit->u, hit->v);
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
