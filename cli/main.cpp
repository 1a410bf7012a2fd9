// bumprad: the command line. `render` solves a scene and writes its image, `retexture`
// re-renders a saved solution, `export` writes one as glTF, `reference` path-traces its
// ground truth, `serve` runs the HTTP service, `worker` solves for it from a shared store,
// `scenes` lists the built-ins.
#include <cstdio>
#include <iostream>
#include <string_view>
#include <vector>

#include "cli/export_command.h"
#include "cli/reference_command.h"
#include "cli/render_command.h"
#include "cli/retexture_command.h"
#include "cli/serve_command.h"
#include "protocol/builtin_scenes.h"

namespace {

constexpr const char* kHelp =
    "bumprad: progressive radiosity with bump textures (Chen & Wu 1990)\n"
    "usage:\n"
    "  bumprad render SCENE -o OUT.(png|exr) [--shots N] [--hemicube R] [--tolerance T]\n"
    "                 [--export-solution S.json] [--bump B.json] [--save-map M]\n"
    "  bumprad retexture M --bump B.json -o OUT.(png|exr)   re-render a saved solution\n"
    "  bumprad export M -o SCENE.glb   a saved solution as a lit glTF binary\n"
    "  bumprad reference SCENE -o REF.exr [--spp N] [--seed S]   path-traced ground truth\n"
    "  bumprad serve [--port P] [--data-dir DIR | --store URL] ...   the HTTP service\n"
    "  bumprad worker --store URL [--workers N] ...   a solver node for serve --store\n"
    "  bumprad scenes           list the built-in scenes (use as builtin:NAME)\n"
    "  bumprad --help\n";

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string_view> args(argv + 1, argv + argc);
  if (args.empty()) {
    std::cerr << kHelp;
    return 2;
  }
  std::string_view command = args.front();
  std::span<const std::string_view> rest(args.data() + 1, args.size() - 1);
  if (command == "render") return bumprad::render_command(rest);
  if (command == "reference") return bumprad::reference_command(rest);
  if (command == "retexture") return bumprad::retexture_command(rest);
  if (command == "export") return bumprad::export_command(rest);
  if (command == "serve") return bumprad::serve_command(rest);
  if (command == "worker") return bumprad::worker_command(rest);
  if (command == "scenes") {
    for (const auto& s : bumprad::builtin_scenes()) std::cout << s.name << "\n";
    return 0;
  }
  if (command == "--help" || command == "-h" || command == "help") {
    std::cout << kHelp;
    return 0;
  }
  std::cerr << "bumprad: unknown command \"" << command << "\"\n" << kHelp;
  return 2;
}
