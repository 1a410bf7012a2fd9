#include "cli/reference_command.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <mutex>
#include <string>

#include "cli/command.h"
#include "common/args.h"
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
  std::vector<std::string> scene;
  ArgParser()
      .text({"-o", "--output"}, r.output)
      .integer({"--spp"}, r.settings.samples_per_pixel, 1, 1 << 20)
      .integer({"--seed"}, r.settings.seed, 0, std::int64_t(1) << 62)
      .text({"--bump"}, r.bump)
      .positional(scene, 1)
      .parse(args);
  if (scene.empty()) throw UsageError("no scene given");
  r.scene = scene.front();
  if (r.output.empty()) throw UsageError("no output image given (-o REF.exr)");
  if (!image_format_for(r.output)) throw UsageError(r.output + ": use .exr, .png or .jpg");
  return r;
}

int run_reference(std::span<const std::string_view> args) {
  const ReferenceArgs a = parse_args(args);
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
}

}  // namespace

int reference_command(std::span<const std::string_view> args) {
  return run_command("reference", kUsage, args, run_reference);
}

}  // namespace bumprad
