#include "cli/retexture_command.h"

#include <cstdio>
#include <iostream>
#include <string>

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

}  // namespace

int retexture_command(std::span<const std::string_view> args) {
  std::string solution_path, bump, output;
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string_view a = args[i];
    bool has_value = i + 1 < args.size();
    if ((a == "-o" || a == "--output") && has_value) {
      output = args[++i];
    } else if (a == "--bump" && has_value) {
      bump = args[++i];
    } else if (!a.starts_with("-") && solution_path.empty()) {
      solution_path = a;
    } else {
      std::cerr << "bumprad retexture: unexpected argument " << a << "\n" << kUsage;
      return 2;
    }
  }
  if (solution_path.empty() || output.empty()) {
    std::cerr << "bumprad retexture: " << (solution_path.empty() ? "no solution file" : "no -o")
              << " given\n"
              << kUsage;
    return 2;
  }
  try {
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
  } catch (const std::exception& e) {
    std::cerr << "bumprad: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace bumprad
