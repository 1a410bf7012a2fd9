// Accuracy against ground truth: bumprad's image of a scene at its settings, and the path
// tracer's own images at growing sample counts, each against a converged path-traced
// reference, in relative RMS error over all pixels (linear radiance) and seconds.
//   build/bin/bumprad-bench-truth SCENE [--spp 1024] [--reference REF.exr]
// The reference is rendered with seed 1 at --spp (or read from REF.exr when that file
// exists, and written there when it does not); the path tracer's own curve uses seed 2, so
// its noise is independent of the reference's. With BUMPRAD_TRUTH_IMAGES=PREFIX set, both
// images are also written as PREFIX-bumprad.exr and PREFIX-reference.exr.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "protocol/scene_source.h"
#include "solver/image.h"
#include "solver/mesh.h"
#include "solver/path_tracer.h"
#include "solver/ray_scene.h"
#include "solver/solution.h"
#include "solver/stopwatch.h"

namespace {

using namespace bumprad;

// sqrt(sum |a - r|^2 / sum |r|^2) over every pixel and channel.
double relative_rms(const Image& a, const Image& r) {
  double diff = 0, norm = 0;
  for (std::size_t i = 0; i < r.rgb.size(); ++i) {
    const double d = double(a.rgb[i]) - double(r.rgb[i]);
    diff += d * d;
    norm += double(r.rgb[i]) * double(r.rgb[i]);
  }
  return std::sqrt(diff / norm);
}

// sum(a) / sum(r): a bias of the whole image's brightness shows here.
double brightness_ratio(const Image& a, const Image& r) {
  double sa = 0, sr = 0;
  for (std::size_t i = 0; i < r.rgb.size(); ++i) {
    sa += a.rgb[i];
    sr += r.rgb[i];
  }
  return sa / sr;
}

}  // namespace

int main(int argc, char** argv) {
  std::string source, cache;
  int spp = 1024;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--spp" && i + 1 < argc)
      spp = std::max(1, std::atoi(argv[++i]));
    else if (a == "--reference" && i + 1 < argc)
      cache = argv[++i];
    else
      source = a;
  }
  if (source.empty()) {
    std::fprintf(stderr, "usage: bumprad-bench-truth SCENE [--spp N] [--reference REF.exr]\n");
    return 2;
  }
  try {
    const Scene scene = load_scene(source);
    const Mesh mesh = build_mesh(scene);
    const RayScene rays(mesh);
    Image reference;
    auto t = Clock::now();
    if (!cache.empty() && std::filesystem::exists(cache)) {
      reference = read_image(cache);
      std::printf("%s: reference read from %s\n", source.c_str(), cache.c_str());
    } else {
      reference = render_reference(scene, mesh, rays, {spp, 1});
      std::printf("%s: reference %d samples a pixel, %.1f s\n", source.c_str(), spp,
                  seconds_since(t));
      if (!cache.empty()) write_image(cache, reference, 1);
    }

    t = Clock::now();
    Solution solution = solve(scene);
    Image image = render(scene, solution);
    std::printf(
        "bumprad at its settings: %zu elements, %d shots, unshot %.2f%%: %.2f%% off, "
        "%.2f s (solve %.2f s); brightness %.4f of the reference's\n",
        solution.stats.elements, solution.stats.shots, 100 * solution.stats.unshot_fraction,
        100 * relative_rms(image, reference), seconds_since(t), solution.stats.seconds_solve,
        brightness_ratio(image, reference));
    if (const char* out = std::getenv("BUMPRAD_TRUTH_IMAGES")) {  // for difference images
      write_image(std::string(out) + "-bumprad.exr", image, 1);
      write_image(std::string(out) + "-reference.exr", reference, 1);
    }

    std::printf("path tracer (seed 2):\n");
    for (int n = 1; n <= spp / 4; n *= 4) {
      t = Clock::now();
      Image traced = render_reference(scene, mesh, rays, {n, 2});
      std::printf("  %5d samples a pixel: %6.2f%% off, %7.2f s\n", n,
                  100 * relative_rms(traced, reference), seconds_since(t));
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bumprad-bench-truth: %s\n", e.what());
    return 1;
  }
}
