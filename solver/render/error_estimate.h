// How far a solution's image is from ground truth, estimated without a reference image: the
// path tracer traces a random sample of the pixels of the view (a copy at most 512 x 1024,
// at the camera's own rays a pixel: an image of larger pixels or more rays is smoother and
// its error smaller), bumprad renders that view, and the relative RMS error over the
// sampled lit pixels is taken with the path tracer's own noise (known per pixel) removed.
// The job's reported error and the solver's tolerance (SolverSettings::tolerance) rest on
// it. The estimator knows images and traced pixels, not solutions: the caller renders the
// view.
#pragma once

#include <cstdint>
#include <vector>

#include "solver/render/path_tracer.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/scene/scene.h"
#include "solver/util/image.h"

namespace bumprad {

struct ErrorEstimate {
  double relative_rms = 0;  // sqrt(sum |a - r|^2 / sum |r|^2), linear radiance
  // Of relative_rms, from the spread of the sampled pixels' squared errors (which carries
  // the path tracer's noise as well as the draw of pixels); half the +-1 sd interval of the
  // squared error mapped through the square root, so it stays finite near 0.
  double standard_error = 0;
  int pixels = 0;
  double seconds = 0;
};

struct ErrorEstimateSettings {
  // 512 pixels of 8,192 paths: a traced pixel's noise, not the draw of pixels, dominates the
  // estimate's spread at errors near 1 % (cornell at 1.05 %, over 8 seeds: 1,024 x 4,096
  // spread 0.15-0.23 %, 512 x 8,192 0.10 %, 256 x 16,384 0.09 %, 4,096 x 1,024 0.20 %).
  int pixels = 512;
  int paths = 8192;
  int max_height = 512;  // the view's rows; its columns at most twice that
  std::uint64_t seed = 1;
};

class ErrorEstimator {
 public:
  // Traces the sample of `scene`'s view on `mesh` (the ground truth does not depend on any
  // solution of it, so one estimator serves every round of a solve).
  ErrorEstimator(const Scene& scene, const Mesh& mesh, const RayScene& rays,
                 const ErrorEstimateSettings& settings = {});
  // The scene with the view to render: the camera within max_height rows and twice as
  // many columns, its aspect kept, 4 x 4 rays a pixel (as the benchmarks measure).
  const Scene& view() const { return view_; }
  // The estimate for bumprad's image of view(); its seconds include the tracing.
  ErrorEstimate estimate(const Image& image) const;

 private:
  Scene view_;
  std::vector<TracedPixel> traced_;
  double trace_seconds_ = 0;
};

// Pixels of scene.camera that show any part of an emitter (straight or in a perfect mirror;
// 8 x 8 rays a pixel), or lie within two pixels of one. A visible light is so much brighter
// than what it lights that it carries nearly all of an image's squared norm (99 % in the
// Cornell box): error over all pixels then measures the light's edges, whose coverage each
// renderer samples differently, and not the lighting.
std::vector<bool> emitter_pixels(const Scene& scene, const Mesh& mesh, const RayScene& rays);

}  // namespace bumprad
