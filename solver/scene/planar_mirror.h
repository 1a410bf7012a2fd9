// Planar mirrors: which surfaces are one (k_s > 0, shininess 0, one plane), their planes, and
// whether a point sees a source through one. Light from a source's virtual image in a planar
// mirror is as exact as the source's own (Wallace, Cohen & Greenberg 1987), so the solve, the
// view pass and the path tracer all treat it as direct light, from here.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/geometric.hpp>

#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/scene/scene.h"

namespace bumprad {

// Per mesh surface: is it a planar mirror? (All its elements mirrors in one plane.)
std::vector<bool> planar_mirrors(const Mesh& mesh, std::span<const Material> materials);

struct PlanarMirror {
  std::uint32_t surface;
  Vec3 point, normal;  // its plane, the normal on its reflecting side
  double specular;     // k_s
  Vec3 reflect(const Vec3& p) const { return p - 2 * glm::dot(p - point, normal) * normal; }
  // A direction's mirror image (an emitter's normal, a light's direction, seen in it).
  Vec3 turn(const Vec3& d) const { return d - 2 * glm::dot(d, normal) * normal; }
  bool in_front(const Vec3& p) const { return glm::dot(p - point, normal) > 0; }
  // Whether `from` sees an image point `distance` along the unit direction `d` (infinity: a
  // direction's image) in this mirror: the ray meets the mirror's front first, and its
  // reflection goes on unoccluded for the rest of the way.
  bool shows(const Vec3& from, const Vec3& d, double distance, const RayScene& rays) const;
};

// One per planar mirror surface.
std::vector<PlanarMirror> planar_mirror_planes(const Mesh& mesh,
                                               std::span<const Material> materials);

}  // namespace bumprad
