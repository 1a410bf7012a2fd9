// How far a solution's image is from ground truth, estimated without a reference image: the
// path tracer traces a random sample of the pixels of the view (at most 128 x 256), bumprad
// renders the same view, and the relative RMS error over the sampled lit pixels is taken
// with the path tracer's own noise (known per pixel) removed. The job's reported error and
// the solver's tolerance (SolverSettings::tolerance) rest on it.
#pragma once

#include <cstdint>
#include <vector>

#include "solver/mesh.h"
#include "solver/ray_scene.h"
#include "solver/scene.h"

namespace bumprad {

struct Solution;

struct ErrorEstimate {
  double relative_rms = 0;    // sqrt(sum |a - r|^2 / sum |r|^2), linear radiance
  double standard_error = 0;  // of relative_rms, from 8 disjoint groups of the pixels
  int pixels = 0;
  double seconds = 0;
};

struct ErrorEstimateSettings {
  int pixels = 1024;
  int paths = 1024;      // a pixel
  int max_height = 128;  // the view's rows; its columns at most twice that
  std::uint64_t seed = 1;
};

ErrorEstimate estimate_error(const Scene& scene, const Solution& solution,
                             const ErrorEstimateSettings& settings = {});

// Pixels of scene.camera that show any part of an emitter (straight or in a perfect mirror;
// 8 x 8 rays a pixel), or lie within two pixels of one. A visible light is so much brighter
// than what it lights that it carries nearly all of an image's squared norm (99 % in the
// Cornell box): error over all pixels then measures the light's edges, whose coverage each
// renderer samples differently, and not the lighting.
std::vector<bool> emitter_pixels(const Scene& scene, const Mesh& mesh, const RayScene& rays);

}  // namespace bumprad
