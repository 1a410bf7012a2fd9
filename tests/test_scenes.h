// Small scenes built in code for the tests: single quads, closed boxes.
#pragma once

#include <vector>

#include "solver/scene.h"

namespace bumprad::test {

// A quad object meshed into nu x nv elements, one patch per element.
Object quad(const std::array<Vec3, 4>& corners, int nu = 1, int nv = 1, int material = 0);

// An axis-aligned w x h rectangle at height z facing down (-z), centred on the z axis.
std::array<Vec3, 4> rectangle_facing_down(double w, double h, double z);

// A scene with one grey material of reflectance `rho` and emission `emission`.
Scene scene_of(std::vector<Object> objects, double rho = 0.5, double emission = 0);

}  // namespace bumprad::test
