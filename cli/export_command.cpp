#include "cli/export_command.h"

#include <cstdio>
#include <string>
#include <vector>

#include "cli/command.h"
#include "common/args.h"
#include "common/atomic_file.h"
#include "protocol/gltf_export.h"
#include "protocol/solution_file.h"

namespace bumprad {
namespace {

constexpr const char* kUsage =
    "usage: bumprad export SOLUTION -o SCENE.glb\n"
    "  SOLUTION is a file written by `bumprad render ... --save-map SOLUTION` or a job's\n"
    "  GET /v1/jobs/{id}/solution\n";

int run_export(std::span<const std::string_view> args) {
  std::string output;
  std::vector<std::string> positional;
  ArgParser().text({"-o", "--output"}, output).positional(positional, 1).parse(args);
  if (positional.empty()) throw UsageError("no solution file given");
  if (output.empty()) throw UsageError("no output file given (-o SCENE.glb)");
  const LoadedSolution loaded = load_solution(positional.front());
  const std::string glb = export_glb(loaded.scene, loaded.solution);
  write_file_atomically(output, glb);
  std::printf("wrote %s (%zu bytes): %zu vertices, %zu elements\n", output.c_str(), glb.size(),
              loaded.solution.mesh->vertices.size(), loaded.solution.mesh->elements.size());
  return 0;
}

}  // namespace

int export_command(std::span<const std::string_view> args) {
  return run_command("export", kUsage, args, run_export);
}

}  // namespace bumprad
