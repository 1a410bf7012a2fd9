#include "solver/scene/planar_mirror.h"

#include "solver/scene/geometry.h"

namespace bumprad {

std::vector<bool> planar_mirrors(const Mesh& mesh, std::span<const Material> materials) {
  std::vector<bool> mirror(mesh.surface_count, true);
  std::vector<std::vector<std::uint32_t>> elements(mesh.surface_count);
  for (std::uint32_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    const Material& m = materials[std::size_t(e.material)];
    mirror[e.surface] = mirror[e.surface] && m.specular > 0 && m.shininess == 0;
    elements[e.surface].push_back(i);
  }
  for (std::uint32_t s = 0; s < mesh.surface_count; ++s)
    mirror[s] = mirror[s] && !elements[s].empty() && coplanar(mesh, elements[s], kOnePlane);
  return mirror;
}

std::vector<PlanarMirror> planar_mirror_planes(const Mesh& mesh,
                                               std::span<const Material> materials) {
  const std::vector<bool> mirror = planar_mirrors(mesh, materials);
  std::vector<bool> listed(mesh.surface_count, false);
  std::vector<PlanarMirror> planes;
  for (const Element& e : mesh.elements)
    if (mirror[e.surface] && !listed[e.surface]) {
      listed[e.surface] = true;
      planes.push_back(
          {e.surface, e.centroid, e.normal, materials[std::size_t(e.material)].specular});
    }
  return planes;
}

bool PlanarMirror::shows(const Vec3& from, const Vec3& d, double distance,
                         const RayScene& rays) const {
  const auto hit = rays.intersect({from, d});
  if (!hit || !hit->front || rays.mesh().elements[hit->element].surface != surface) return false;
  const double epsilon = ray_epsilon(rays.mesh());
  const Vec3 on_mirror = from + hit->t * d;
  return !rays.occluded({on_mirror + normal * epsilon, turn(d)}, distance - hit->t - 2 * epsilon);
}

}  // namespace bumprad
