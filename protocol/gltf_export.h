// A solution as a glTF 2.0 binary (.glb) that any glTF viewer shows lit: the meshed scene as
// solved, each vertex's light in COLOR_0 under KHR_materials_unlit, the physical radiosity
// in a custom attribute, the scene's camera. Layout and units: docs/export.md.
#pragma once

#include <string>

#include "solver/solution.h"

namespace bumprad {

// The .glb's bytes for `solution`, solved from `scene` (its materials, camera and exposure).
std::string export_glb(const Scene& scene, const Solution& solution);

}  // namespace bumprad
