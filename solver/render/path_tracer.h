// The ground truth: an unbiased path tracer (Kajiya 1986) of exactly the scene model bumprad
// solves, to measure the radiosity solution against. Same meshed geometry (one-sided
// elements), emission as radiosity E (Lambertian radiance E/pi from the front side), diffuse
// reflectance rho (times a colour texture), a specular fraction k_s reflected as a mirror or
// a Phong lobe (cos^shininess about the mirror direction, renormalised above the surface, as
// the view pass does), and bump functions as Blinn's perturbed shading normal. Direct light
// is sampled at every diffuse bounce (next-event estimation), and so is light through each
// planar mirror, to the emitter's image: light a flat mirror throws on a diffuse surface
// would otherwise be found only by paths that happen to bounce into a small emitter's
// image. At glossy surfaces the emitters are sampled too, weighed against the lobe
// (multiple importance sampling). Russian roulette ends paths.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <stop_token>
#include <vector>

#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/util/image.h"

namespace bumprad {

struct ReferenceSettings {
  int samples_per_pixel = 256;
  std::uint64_t seed = 1;  // the image is a function of the scene, spp and seed alone
};

// Called after each row with the fraction done; from any thread, so it must be cheap.
using ReferenceProgress = std::function<void(double fraction)>;

// Radiance per pixel (W m^-2 sr^-1), in the view pass's units: the same camera, the same
// mesh. `stop` ends it within a row; the image is then unfinished.
Image render_reference(const Scene& scene, const Mesh& mesh, const RayScene& rays,
                       const ReferenceSettings& settings, const ReferenceProgress& progress = {},
                       std::stop_token stop = {});

struct PixelIndex {
  int x, y;
};
struct TracedPixel {
  PixelIndex pixel;
  Rgb radiance;     // as render_reference gives it for the same settings
  double variance;  // of that mean, channels summed: its own noise
};
// Only the given pixels of the reference, with their noise (for estimating error without a
// whole reference image).
std::vector<TracedPixel> trace_pixels(const Scene& scene, const Mesh& mesh, const RayScene& rays,
                                      std::span<const PixelIndex> pixels,
                                      const ReferenceSettings& settings);

}  // namespace bumprad
