// What a solve reports as it goes and when it ends: the snapshot a refinement step hands out
// (enough to render a preview), the time a shot took, and the figures users are told.
#pragma once

#include <cstddef>
#include <vector>

#include "solver/util/math.h"

namespace bumprad {

struct ShotTiming {
  double render_s = 0, accumulate_s = 0, texture_s = 0, specular_s = 0, total_s = 0;
};

// A finished (or stopped) solve, as reported to users.
struct SolveStats {
  int shots = 0;
  std::size_t elements = 0;
  double seconds_solve = 0;  // wall time, hemi-cube set-up included, texture work excluded
  double seconds_setup = 0;  // of that: mesh, rays, open shares, near field, GL context
  double unshot_fraction = 0;
  double seconds_texture = 0;  // building the perturbed map (gather pass or shooting)
  // With SolverSettings::tolerance: the image's estimated relative RMS error against ground
  // truth and its standard error (error_estimate.h); 0 when not estimated.
  double estimated_error = 0, estimated_error_se = 0;
  // With a tolerance: the rays a pixel across it chose for the view, if more than the
  // camera's (SolutionView renders with them); 0: the camera's.
  int antialias = 0;
  std::size_t perturbed_elements = 0;
  std::size_t map_values = 0;            // numbers a map vertex stores per channel
  std::size_t non_diffuse_elements = 0;  // with a specular fraction
};

// What a refinement step hands out: enough to render a preview.
struct Snapshot {
  int shots = 0;
  double unshot_fraction = 0;
  bool final = false;
  std::vector<Rgb> radiosity;  // per element, with the ambient term for display
  std::vector<Rgb> direct;     // per element, the part of it straight from the emitters
};

}  // namespace bumprad
