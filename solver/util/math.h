// The vector types and constants every part of the solver shares.
#pragma once

#include <numbers>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace bumprad {

using Vec3 = glm::dvec3;
using Rgb = glm::dvec3;

inline constexpr double kPi = std::numbers::pi;

}  // namespace bumprad
