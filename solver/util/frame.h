// An orthonormal tangent frame (z the surface normal), the one every part of the solver
// uses to go between world and local directions: hemi-cubes, Phong lobes, map bases.
#pragma once

#include <glm/geometric.hpp>

#include "solver/util/math.h"

namespace bumprad {

// An orthonormal right-handed frame; z is the surface normal N.
struct Frame {
  Vec3 x, y, z;
  Vec3 to_world(const Vec3& local) const { return local.x * x + local.y * y + local.z * z; }
  Vec3 to_local(const Vec3& world) const {
    return {glm::dot(world, x), glm::dot(world, y), glm::dot(world, z)};
  }
};

// A frame about the unit normal n, turned by `angle` radians about n.
Frame frame_about(const Vec3& n, double angle = 0);

}  // namespace bumprad
