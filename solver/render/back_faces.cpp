#include "solver/render/back_faces.h"

#include <algorithm>
#include <cmath>

#include "solver/scene/camera.h"

namespace bumprad {

std::vector<BackFacing> back_facing_objects(const Scene& scene, const Mesh& mesh,
                                            const RayScene& rays) {
  const Camera& c = scene.camera;
  const int nx = std::min(64, c.width), ny = std::min(64, c.height);
  const PinholeCamera camera(c);
  std::vector<int> front(scene.objects.size()), back(scene.objects.size());
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const auto hit =
          rays.intersect(camera.ray((i + 0.5) * c.width / nx, (j + 0.5) * c.height / ny));
      if (!hit) continue;
      const std::uint32_t o = mesh.elements[hit->element].object;
      ++(hit->front ? front : back)[o];
    }
  std::vector<BackFacing> out;
  for (std::uint32_t o = 0; o < scene.objects.size(); ++o) {
    const double share = double(back[o]) / (nx * ny);
    if (back[o] > front[o] && share >= 0.01) out.push_back({o, share});
  }
  return out;
}

std::vector<std::string> back_face_warnings(const Scene& scene, const Mesh& mesh,
                                            const RayScene& rays) {
  std::vector<std::string> out;
  for (const BackFacing& b : back_facing_objects(scene, mesh, rays)) {
    const std::string& name = scene.objects[b.object].name;
    out.push_back("object \"" +
                  (name.empty() ? "objects[" + std::to_string(b.object) + "]" : name) +
                  "\": " + std::to_string(int(std::lround(100 * b.share))) +
                  " % of the image shows its back faces, which are black (surfaces are "
                  "one-sided: flip_normals, or turn the model's triangles)");
  }
  return out;
}

}  // namespace bumprad
