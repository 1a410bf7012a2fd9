#include "cli/reference_command.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <mutex>
#include <string>

#include "cli/usage_error.h"
#include "common/stopwatch.h"
#include "protocol/scene_source.h"
#include "solver/render/path_tracer.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/util/image.h"

namespace bumprad {
namespace {

constexpr const char* kUsage =
    "usage: bumprad reference SCENE -o REF.(exr|png) [--spp N] [--seed S] [--bump B.json]\n"
    "  path-traced ground truth of SCENE (a JSON file or builtin:NAME): the same geometry,\n"
    "  materials, camera and bump functions as `bumprad render`, unbiased; --spp 256 and\n"
    "  --seed 1 by default; the image depends on the scene, --spp and --seed alone\n";

struct ReferenceArgs {
  std::string scene, output, bump;
  ReferenceSettings settings;
};

ReferenceArgs parse_args(std::span<const std::string_view> args) {
  ReferenceArgs r;
  auto value = [&](std::size_t& i) {
    if (i + 1 >= args.size()) throw UsageError(std::string(args[i]) + " needs a value");
    return std::string(args[++i]);
  };
  auto count = [&](std::size_t& i, long long max) {
    std::string flag(args[i]), v = value(i);
    try {
      std::size_t used = 0;
      long long n = std::stoll(v, &used);
      if (used == v.size() && n >= 0 && n <= max) return n;
    } catch (const std::exception&) {
    }
    throw UsageError(flag + ": \"" + v + "\" is not a whole number up to " + std::to_string(max));
  };
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string_view a = args[i];
    if (a == "-o" || a == "--output")
      r.output = value(i);
    else if (a == "--spp")
      r.settings.samples_per_pixel = int(std::max(1LL, count(i, 1 << 20)));
    else if (a == "--seed")
      r.settings.seed = std::uint64_t(count(i, 1LL << 62));
    else if (a == "--bump")
      r.bump = value(i);
    else if (a.starts_with("-"))
      throw UsageError("unknown option " + std::string(a));
    else if (r.scene.empty())
      r.scene = a;
    else
      throw UsageError("more than one scene given");
  }
  if (r.scene.empty()) throw UsageError("no scene given");
  if (r.output.empty()) throw UsageError("no output image given (-o REF.exr)");
  if (!image_format_for(r.output)) throw UsageError(r.output + ": use .exr, .png or .jpg");
  return r;
}

}  // namespace

int reference_command(std::span<const std::string_view> args) {
  ReferenceArgs a;
  try {
    a = parse_args(args);
  } catch (const UsageError& e) {
    std::cerr << "bumprad reference: " << e.what() << "\n" << kUsage;
    return 2;
  }
  try {
    Scene scene = load_scene(a.scene);
    if (!a.bump.empty()) apply_bump_file(a.bump, scene);
    const Mesh mesh = build_mesh(scene);
    const RayScene rays(mesh);
    // On a terminal the progress line rewrites itself; in a log, a line every 10 %.
    const bool tty = ::isatty(STDERR_FILENO);
    const auto t0 = Clock::now();
    std::mutex mutex;
    int shown = -1;
    Image image = render_reference(scene, mesh, rays, a.settings, [&](double done) {
      std::lock_guard lock(mutex);
      const int percent = int(100 * done);
      if (percent == shown || (!tty && percent % 10 != 0)) return;
      shown = percent;
      std::fprintf(stderr, "%sbumprad reference: %3d%%, %.1f s%s", tty ? "\r" : "", percent,
                   seconds_since(t0), tty ? "" : "\n");
    });
    if (tty) std::fputc('\n', stderr);
    write_image(a.output, image, scene.camera.exposure);
    std::printf("wrote %s (%dx%d): %d samples a pixel, seed %llu, %zu elements, %.2f s\n",
                a.output.c_str(), image.width, image.height, a.settings.samples_per_pixel,
                static_cast<unsigned long long>(a.settings.seed), mesh.elements.size(),
                seconds_since(t0));
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "bumprad: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace bumprad
