// The vector types every part of the solver shares.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace bumprad {

using Vec3 = glm::dvec3;
using Rgb = glm::dvec3;

}  // namespace bumprad
