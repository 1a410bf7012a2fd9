#include "cli/render_command.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/command.h"
#include "common/args.h"
#include "common/atomic_file.h"
#include "common/stopwatch.h"
#include "protocol/scene_json.h"
#include "protocol/scene_source.h"
#include "protocol/solution_file.h"
#include "protocol/solution_json.h"
#include "solver/render/back_faces.h"
#include "solver/solution.h"
#include "solver/util/image.h"

namespace bumprad {
namespace {

constexpr const char* kUsage =
    "usage: bumprad render SCENE -o OUT.(png|exr) [--shots N] [--hemicube R] [--tolerance T]\n"
    "                      [--export-solution S.json] [--bump B.json] [--save-map M]\n"
    "  --tolerance T: solve on until the image's estimated error against path-traced ground\n"
    "                 truth is below T (e.g. 0.02), or stops falling: more shots, then more\n"
    "                 rays a pixel, then finer elements; prints the estimate\n"
    "  SCENE is a JSON file or builtin:NAME (see `bumprad scenes`)\n";

struct RenderArgs {
  std::string scene, output, solution, bump, save_map;
  nlohmann::json overrides = nlohmann::json::object();  // solver settings from flags
};

RenderArgs parse_args(std::span<const std::string_view> args) {
  RenderArgs r;
  std::optional<std::int64_t> shots, hemicube;
  std::optional<double> tolerance;
  std::vector<std::string> scene;
  // The solver settings' own ranges are the scene format's: its validation checks them.
  ArgParser()
      .text({"-o", "--output"}, r.output)
      .integer({"--shots"}, shots, INT64_MIN, INT64_MAX)
      .integer({"--hemicube"}, hemicube, INT64_MIN, INT64_MAX)
      .number({"--tolerance"}, tolerance, -1e300, 1e300)
      .text({"--export-solution"}, r.solution)
      .text({"--bump"}, r.bump)
      .text({"--save-map"}, r.save_map)
      .positional(scene, 1)
      .parse(args);
  if (shots) r.overrides["max_shots"] = *shots;
  if (hemicube) r.overrides["hemicube_resolution"] = *hemicube;
  if (tolerance) r.overrides["tolerance"] = *tolerance;
  if (scene.empty()) throw UsageError("no scene given");
  r.scene = scene.front();
  if (r.output.empty()) throw UsageError("no output image given (-o OUT.png or OUT.exr)");
  return r;
}

// What the solve and the view pass did, for the user.
void print_summary(const std::string& output, const Image& image, const Scene& scene,
                   const Solution& solution, double seconds_view) {
  const SolveStats& stats = solution.stats;
  std::printf(
      "wrote %s (%dx%d): %d shots, %zu elements, %zu patches, unshot %.2f%%, solve %.2f s, "
      "view %.2f s\n",
      output.c_str(), image.width, image.height, stats.shots, stats.elements,
      solution.mesh->patches.size(), 100 * stats.unshot_fraction, stats.seconds_solve,
      seconds_view);
  if (stats.estimated_error > 0)
    std::printf(
        "estimated error against path-traced ground truth: %.1f %% +- %.1f %% (tolerance "
        "%.1f %%)\n",
        100 * stats.estimated_error, 100 * stats.estimated_error_se, 100 * scene.solver.tolerance);
  if (stats.antialias > 0 || !solution.refinements.empty()) {
    const int n = rendered_antialias(scene, solution);
    std::printf("refined: %d x %d rays a pixel, %zu levels of subdivision\n", n, n,
                solution.refinements.size());
  }
  if (stats.non_diffuse_elements)
    std::printf(
        "non-diffuse: %zu elements (specular transfer in the solve, reflections in "
        "the view)\n",
        stats.non_diffuse_elements);
  if (solution.map)
    std::printf("perturbed map: %zu elements, %zu %s a vertex, %s, %.3f s\n",
                stats.perturbed_elements, stats.map_values,
                scene.solver.map.basis == MapBasisKind::SphericalHarmonics ? "harmonics"
                                                                           : "sampled normals",
                scene.solver.texture == TextureMode::Gather ? "gathered" : "shot",
                stats.seconds_texture);
}

int run_render(std::span<const std::string_view> args) {
  const RenderArgs a = parse_args(args);
  std::string scene_json;
  Scene scene = load_scene(a.scene, &scene_json);
  try {
    apply_solver_settings(a.overrides, scene.solver, "");
  } catch (const SceneError& e) {
    const std::string flag = e.pointer() == "/max_shots"   ? "--shots"
                             : e.pointer() == "/tolerance" ? "--tolerance"
                                                           : "--hemicube";
    std::string msg = e.what();
    throw UsageError(flag + msg.substr(msg.find(':')));
  }
  if (!a.bump.empty()) apply_bump_file(a.bump, scene);

  // On a terminal the progress line rewrites itself every step; in a log, a line a second.
  const bool tty = ::isatty(STDERR_FILENO);
  auto last_line = Clock::now();
  Solution solution = solve(scene, [&](const Snapshot& s, const Solution&) {
    if (!tty && !s.final && seconds_since(last_line) < 1) return true;
    last_line = Clock::now();
    std::fprintf(stderr, "%sbumprad: shot %d/%d, unshot %.2f%%%s", tty ? "\r" : "", s.shots,
                 scene.solver.max_shots, 100 * s.unshot_fraction, tty ? "" : "\n");
    return true;
  });
  if (tty) std::fputc('\n', stderr);
  for (const std::string& w : back_face_warnings(scene, *solution.mesh, *solution.rays))
    std::fprintf(stderr, "bumprad: warning: %s\n", w.c_str());

  auto t1 = Clock::now();
  Image image = render(scene, solution);
  write_image(a.output, image, scene.camera.exposure);
  double seconds_view = seconds_since(t1);

  if (!a.solution.empty())
    write_file_atomically(
        a.solution, solution_to_json(scene, *solution.mesh, solution.radiosity, solution.stats));
  print_summary(a.output, image, scene, solution, seconds_view);
  if (!a.solution.empty()) std::printf("wrote %s\n", a.solution.c_str());
  if (!a.save_map.empty()) {
    save_solution(a.save_map, scene_json, solution);
    std::printf("wrote %s (re-texture it with `bumprad retexture`)\n", a.save_map.c_str());
  }
  return 0;
}

}  // namespace

int render_command(std::span<const std::string_view> args) {
  return run_command("render", kUsage, args, run_render);
}

}  // namespace bumprad
