// Accuracy against ground truth: bumprad's image of a scene at its settings, and the path
// tracer's own images at growing sample counts, each against a converged path-traced
// reference, in relative RMS error (linear radiance) over the lit surfaces, with emitters'
// pixels masked, and over all pixels; and seconds.
//   build/bin/bumprad-bench-truth SCENE [--spp 1024] [--reference REF.exr]
// The reference is rendered with seed 1 at --spp (or read from REF.exr when that file
// exists, and written there when it does not); the path tracer's own curve uses seed 2, so
// its noise is independent of the reference's. With BUMPRAD_TRUTH_IMAGES=PREFIX set, both
// images are also written as PREFIX-bumprad.exr and PREFIX-reference.exr.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "protocol/scene_source.h"
#include "solver/camera.h"
#include "solver/image.h"
#include "solver/mesh.h"
#include "solver/path_tracer.h"
#include "solver/ray_scene.h"
#include "solver/solution.h"
#include "solver/stopwatch.h"

namespace {

using namespace bumprad;

// Pixels that show an emitter, or lie within two pixels of one. A visible light is so much
// brighter than what it lights that it carries nearly all of an image's squared norm (99 %
// in the Cornell box): error over all pixels then measures the light's edges, whose
// coverage each renderer samples differently, and not the lighting.
bool emits(const Rgb& e) {
  return e.r + e.g + e.b > 0;
}

std::vector<bool> emitter_pixels(const Scene& scene, const Mesh& mesh, const RayScene& rays) {
  const Camera& c = scene.camera;
  const PinholeCamera pinhole(c);
  std::vector<bool> light(std::size_t(c.width) * std::size_t(c.height), false);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      if (auto hit = rays.intersect(pinhole.ray(x + 0.5, y + 0.5)))
        light[std::size_t(y) * std::size_t(c.width) + std::size_t(x)] =
            emits(scene.materials[std::size_t(mesh.elements[hit->element].material)].emission);
  std::vector<bool> near = light;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int sx = x + dx, sy = y + dy;
          if (sx >= 0 && sy >= 0 && sx < c.width && sy < c.height &&
              light[std::size_t(sy) * std::size_t(c.width) + std::size_t(sx)])
            near[std::size_t(y) * std::size_t(c.width) + std::size_t(x)] = true;
        }
  return near;
}

struct Comparison {
  double surfaces;    // relative RMS over pixels that show no emitter
  double all;         // relative RMS over every pixel
  double brightness;  // sum(a) / sum(r) over the surfaces' pixels
};

// sqrt(sum |a - r|^2 / sum |r|^2), linear radiance, every channel.
Comparison compare(const Image& a, const Image& r, const std::vector<bool>& emitter) {
  double diff[2] = {0, 0}, norm[2] = {0, 0}, sa = 0, sr = 0;
  for (std::size_t i = 0; i < r.rgb.size(); ++i) {
    const double d = double(a.rgb[i]) - double(r.rgb[i]);
    const bool surface = !emitter[i / 3];
    for (int k = 0; k < 2; ++k)
      if (k == 0 || surface) {
        diff[k] += d * d;
        norm[k] += double(r.rgb[i]) * double(r.rgb[i]);
      }
    if (surface) sa += a.rgb[i], sr += r.rgb[i];
  }
  return {std::sqrt(diff[1] / norm[1]), std::sqrt(diff[0] / norm[0]), sa / sr};
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
    if (const char* out = std::getenv("BUMPRAD_TRUTH_IMAGES")) {  // for difference images
      write_image(std::string(out) + "-bumprad.exr", image, 1);
      write_image(std::string(out) + "-reference.exr", reference, 1);
    }

    // The path tracer at n = spp/4 samples is off by sqrt(noise_n^2 + noise_ref^2) with
    // noise_n = 2 noise_ref (noise falls as 1/sqrt(n)): so noise_ref = that error / sqrt(5).
    // bumprad's image does not share the reference's noise, so its own error is
    // sqrt(measured^2 - noise_ref^2).
    std::printf("path tracer (seed 2), lit surfaces and all pixels:\n");
    double at_quarter = 0;
    for (int n = 1; n <= spp / 4; n *= 4) {
      t = Clock::now();
      Image traced = render_reference(scene, mesh, rays, {n, 2});
      const double s = seconds_since(t);
      const Comparison p = compare(traced, reference, emitter);
      std::printf("  %5d samples a pixel: %6.2f%% off (all %6.2f%%), %7.2f s\n", n,
                  100 * p.surfaces, 100 * p.all, s);
      if (n * 4 == spp) at_quarter = p.surfaces;
    }
    if (at_quarter > 0) {
      const double noise = at_quarter / std::sqrt(5.0);
      std::printf(
          "the reference's own noise on lit surfaces: %.2f%%; bumprad with it taken out: %.2f%% "
          "off\n",
          100 * noise, 100 * std::sqrt(std::max(0.0, c.surfaces * c.surfaces - noise * noise)));
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bumprad-bench-truth: %s\n", e.what());
    return 1;
  }
}
