#include "cli/retexture_command.h"

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "cli/command.h"
#include "common/args.h"
#include "common/stopwatch.h"
#include "protocol/scene_source.h"
#include "protocol/solution_file.h"
#include "solver/solution.h"
#include "solver/util/image.h"

namespace bumprad {
namespace {

constexpr const char* kUsage =
    "usage: bumprad retexture SOLUTION --bump B.json -o OUT.(png|exr)\n"
    "  SOLUTION is a file written by `bumprad render ... --save-map SOLUTION`\n";

int run_retexture(std::span<const std::string_view> args) {
  std::string bump, output;
  std::vector<std::string> positional;
  ArgParser()
      .text({"-o", "--output"}, output)
      .text({"--bump"}, bump)
      .positional(positional, 1)
      .parse(args);
  if (positional.empty()) throw UsageError("no solution file given");
  if (output.empty()) throw UsageError("no output image given (-o OUT.png or OUT.exr)");
  const std::string& solution_path = positional.front();
  auto t0 = Clock::now();
  LoadedSolution loaded = load_solution(solution_path);
  if (!bump.empty()) apply_bump_file(bump, loaded.scene);
  if (!loaded.solution.map)
    std::cerr << "bumprad: warning: " << solution_path
              << " has no perturbed map (no bumpy object, or texture none): rendering smooth\n";
  double seconds_load = seconds_since(t0);
  auto t1 = Clock::now();
  Image image = render(loaded.scene, loaded.solution);
  double seconds_render = seconds_since(t1);
  write_image(output, image, loaded.scene.camera.exposure);
  std::printf("wrote %s (%dx%d) from %s: load %.3f s, re-texture %.3f s, no solve\n",
              output.c_str(), image.width, image.height, solution_path.c_str(), seconds_load,
              seconds_render);
  return 0;
}

}  // namespace

int retexture_command(std::span<const std::string_view> args) {
  return run_command("retexture", kUsage, args, run_retexture);
}

}  // namespace bumprad
