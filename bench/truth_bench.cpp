// Accuracy against ground truth: bumprad's image of a scene at its settings, and the path
// tracer's own images at growing sample counts, each against a converged path-traced
// reference, in relative RMS error (linear radiance) over the lit surfaces, with emitters'
// pixels masked, and over all pixels; and seconds.
//   build/bin/bumprad-bench-truth SCENE [--spp 1024] [--reference REF.exr]
// The reference is rendered with seed 1 at --spp (or read from REF.exr when that file
// exists, and written there when it does not); the path tracer's own curve uses seed 2, so
// its noise is independent of the reference's. With BUMPRAD_TRUTH_IMAGES=PREFIX set, both
// images are also written as PREFIX-bumprad.exr and PREFIX-reference.exr, and where they
// differ as PREFIX-difference.png (red: bumprad brighter, blue: darker, full at 20 %).
// A reference from another renderer (scripts/cycles.sh: Cycles) is read from REF.exr; with
// --noise-reference REF2.exr, the same render at another seed, its own noise is measured from
// the two rather than estimated from the path tracer's curve (--no-path-tracer skips the
// curve). --width W renders at W pixels across (the camera's aspect kept), to match a
// reference of that size. A scene with an object named "floor" also gets the floor's
// speckle: the high-pass of bumprad's image minus the reference's (truth_metrics.h), and,
// with --noise-reference, the reference's own taken out. --estimator-seeds K estimates
// bumprad's image with the error estimator (error_estimate.h) at seeds 1..K, to set its
// spread beside the measured error.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "bench/truth_metrics.h"
#include "common/args.h"
#include "common/stopwatch.h"
#include "protocol/scene_source.h"
#include "solver/render/error_estimate.h"
#include "solver/render/path_tracer.h"
#include "solver/scene/camera.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/solution.h"
#include "solver/util/image.h"

constexpr const char* kUsage =
    "usage: bumprad-bench-truth SCENE [--spp N] [--reference REF.exr] [--noise-reference "
    "REF2.exr] [--width W] [--no-path-tracer] [--estimator-seeds K]\n";

int main(int argc, char** argv) {
  using namespace bumprad;
  std::string source, cache, second;
  int spp = 1024, width = 0, estimator_seeds = 0;
  bool skip_curve = false;
  std::vector<std::string> positional;
  ArgParser()
      .integer({"--spp"}, spp, 1, 1 << 24)
      .text({"--reference"}, cache)
      .text({"--noise-reference"}, second)
      .integer({"--width"}, width, 8, 8192)
      .toggle({"--no-path-tracer"}, skip_curve)
      .integer({"--estimator-seeds"}, estimator_seeds, 0, 64)
      .positional(positional, 1)
      .parse_or_exit(argc, argv, kUsage);
  if (positional.empty()) {
    std::fprintf(stderr, "bumprad-bench-truth: no scene given\n%s", kUsage);
    return 2;
  }
  source = positional.front();
  try {
    Scene scene = load_scene(source);
    if (width > 0) {
      scene.camera.height =
          std::max(1, int(std::lround(double(width) * scene.camera.height / scene.camera.width)));
      scene.camera.width = width;
    }
    const Mesh mesh = build_mesh(scene);
    const RayScene rays(mesh);
    auto read_sized = [&](const std::string& path) {
      Image im = read_image(path);
      if (im.width != scene.camera.width || im.height != scene.camera.height)
        throw std::runtime_error(path + " is " + std::to_string(im.width) + " x " +
                                 std::to_string(im.height) + ", the scene renders " +
                                 std::to_string(scene.camera.width) + " x " +
                                 std::to_string(scene.camera.height) + " (--width)");
      return im;
    };
    Image reference;
    auto t = Clock::now();
    if (!cache.empty() && std::filesystem::exists(cache)) {
      reference = read_sized(cache);
      std::printf("%s: reference read from %s\n", source.c_str(), cache.c_str());
    } else {
      reference = render_reference(scene, mesh, rays, {spp, 1});
      std::printf("%s: reference %d samples a pixel, %.1f s\n", source.c_str(), spp,
                  seconds_since(t));
      if (!cache.empty()) write_image(cache, reference, 1);
    }

    const std::vector<bool> emitter = emitter_pixels(scene, mesh, rays);
    t = Clock::now();
    Solution solution = solve(scene);
    Image image = render(scene, solution);
    const double seconds = seconds_since(t);
    const Comparison c = compare(image, reference, emitter);
    std::printf(
        "bumprad at its settings: %zu elements, %d shots, unshot %.2f%%, %.2f s (solve %.2f "
        "s):\n  lit surfaces %.2f%% off, brightness %.4f of the reference's; all pixels %.2f%% "
        "off\n",
        solution.stats.elements, solution.stats.shots, 100 * solution.stats.unshot_fraction,
        seconds, solution.stats.seconds_solve, 100 * c.surfaces, c.brightness, 100 * c.all);
    if (solution.stats.estimated_error > 0)  // solver.tolerance: its own estimate, to compare
      std::printf("  its own estimate (solver.tolerance): %.2f%% +- %.2f%%\n",
                  100 * solution.stats.estimated_error, 100 * solution.stats.estimated_error_se);
    if (const char* out = std::getenv("BUMPRAD_TRUTH_IMAGES")) {  // for difference images
      write_image(std::string(out) + "-bumprad.exr", image, 1);
      write_image(std::string(out) + "-reference.exr", reference, 1);
      write_image(std::string(out) + "-difference.png", difference_image(image, reference, emitter),
                  1);
    }

    // The path tracer at n = spp/4 samples is off by sqrt(noise_n^2 + noise_ref^2) with
    // noise_n = 2 noise_ref (noise falls as 1/sqrt(n)): so noise_ref = that error / sqrt(5).
    // bumprad's image does not share the reference's noise, so its own error is
    // sqrt(measured^2 - noise_ref^2).
    double at_quarter = 0;
    if (!skip_curve) std::printf("path tracer (seed 2), lit surfaces and all pixels:\n");
    for (int n = 1; !skip_curve && n <= spp / 4; n *= 4) {
      t = Clock::now();
      Image traced = render_reference(scene, mesh, rays, {n, 2});
      const double s = seconds_since(t);
      const Comparison p = compare(traced, reference, emitter);
      std::printf("  %5d samples a pixel: %6.2f%% off (all %6.2f%%), %7.2f s\n", n,
                  100 * p.surfaces, 100 * p.all, s);
      if (n * 4 == spp) at_quarter = p.surfaces;
    }
    // Two renders of the reference at different seeds differ by sqrt(2) times its noise.
    const Image reseeded = second.empty() ? Image() : read_sized(second);
    const double noise = !second.empty()
                             ? compare(reseeded, reference, emitter).surfaces / std::sqrt(2.0)
                             : at_quarter / std::sqrt(5.0);
    if (noise > 0)
      std::printf(
          "the reference's own noise on lit surfaces (%s): %.2f%%; bumprad with it taken out: "
          "%.2f%% off\n",
          second.empty() ? "from the path tracer's curve" : "from its second seed", 100 * noise,
          100 * without_noise(c.surfaces, noise));
    // The estimator's own spread over its seeds (each a different random set of pixels).
    double sum = 0, sum2 = 0;
    for (int seed = 1; seed <= estimator_seeds; ++seed) {
      ErrorEstimateSettings settings;
      settings.seed = std::uint64_t(seed);
      const ErrorEstimator estimator(scene, *solution.mesh, *solution.rays, settings);
      const ErrorEstimate e = estimator.estimate(render(estimator.view(), solution));
      std::printf("  estimator seed %d: %.2f%% +- %.2f%% (%.1f s)\n", seed, 100 * e.relative_rms,
                  100 * e.standard_error, e.seconds);
      sum += e.relative_rms;
      sum2 += e.relative_rms * e.relative_rms;
    }
    if (estimator_seeds > 1) {
      const double mean = sum / estimator_seeds;
      std::printf("estimator over %d seeds: mean %.2f%%, spread (sd) %.2f%%\n", estimator_seeds,
                  100 * mean,
                  100 * std::sqrt(std::max(0.0, sum2 / estimator_seeds - mean * mean) *
                                  estimator_seeds / (estimator_seeds - 1)));
    }
    // Speckle on the floor (the object named so, if any): bumprad's high-pass against the
    // reference's, whose own noise the second seed measures.
    const auto floor = std::find_if(scene.objects.begin(), scene.objects.end(),
                                    [](const Object& o) { return o.name == "floor"; });
    if (floor != scene.objects.end()) {
      const std::vector<int> objects = pixel_objects(scene, mesh, rays);
      const int which = int(floor - scene.objects.begin());
      const double raw = speckle(image, reference, objects, which);
      std::printf("floor speckle (5 x 5 high-pass RMS of bumprad - reference, / mean): %.2f%%",
                  100 * raw);
      if (!second.empty()) {
        const double own = speckle(reseeded, reference, objects, which) / std::sqrt(2.0);
        std::printf("; the reference's own %.2f%%; bumprad with it taken out: %.2f%%", 100 * own,
                    100 * without_noise(raw, own));
      }
      std::printf("\n");
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bumprad-bench-truth: %s\n", e.what());
    return 1;
  }
}
