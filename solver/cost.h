// What a solve and a render will cost, in seconds of a 2-core machine, estimated from the
// scene alone before any work starts, so that a service can refuse work it cannot afford:
// the shots a solve is expected to take (from its patches, their reflectance and the unshot
// target), each costed by the counts that drive its loops. bumprad-bench-scale prints the
// measured over the estimated; calibrated there and on the built-ins to within 0.3-3.
#pragma once

#include <string>

#include "solver/scene/scene.h"

namespace bumprad {

struct CostEstimate {
  double solve_s = 0;        // the set-up, the expected shots of every adaptive level, the
                             // gather, and the error estimates of a tolerance
  double shots = 0;          // expected_shots()
  double setup_s = 0;        // of which the set-up: meshing, rays, open shares, near sets
  double render_s = 0;       // one full-quality view pass of the scene's camera
  double render_mesh_s = 0;  // of which what grows with the mesh, not the pixels
  std::string solve_terms, render_terms;  // the counts behind each, for messages
};

CostEstimate estimate_cost(const Scene& scene);

// The shots a solve of `scene` is expected to take (at most max_shots).
double expected_shots(const Scene& scene);

// Render cost alone (re-texturing with a new camera or bump function).
CostEstimate estimate_render_cost(const Scene& scene);

}  // namespace bumprad
