// The solution export format (`bumprad render --export-solution`): every element's solved
// radiosity, and the solve's statistics.
#pragma once

#include <span>
#include <string>

#include "solver/radiosity/progressive.h"
#include "solver/scene/mesh.h"

namespace bumprad {

// {"elements": [{"id", "object", "area", "radiosity": [r,g,b]}...], "stats": {...}}.
// Radiosity is the solved B in W/m^2, without the display-only ambient term.
std::string solution_to_json(const Scene& scene, const Mesh& mesh, std::span<const Rgb> radiosity,
                             const SolveStats& stats);

}  // namespace bumprad
