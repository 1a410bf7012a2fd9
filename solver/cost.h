// What a solve and a render will cost, in seconds of a 2-core machine, estimated from the
// scene alone before any work starts, so that a service can refuse work it cannot afford.
// The model is linear in the counts that drive each loop and errs on the expensive side.
#pragma once

#include <string>

#include "solver/scene/scene.h"

namespace bumprad {

struct CostEstimate {
  double solve_s = 0;        // the set-up, every shot at max_shots, every adaptive level, the
                             // gather, and the error estimates of a tolerance
  double setup_s = 0;        // of which the set-up: meshing, rays, open shares, near sets
  double render_s = 0;       // one full-quality view pass of the scene's camera
  double render_mesh_s = 0;  // of which what grows with the mesh, not the pixels
  std::string solve_terms, render_terms;  // the counts behind each, for messages
};

CostEstimate estimate_cost(const Scene& scene);

// Render cost alone (re-texturing with a new camera or bump function).
CostEstimate estimate_render_cost(const Scene& scene);

}  // namespace bumprad
