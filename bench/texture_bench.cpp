// Texture benchmark: the cost of the perturbed radiosity map, and of re-texturing.
//   build/bin/bumprad-bench-texture [SCENE...]      (default: paper-room and wrinkled-box)
// For each scene: the whole solve with texture none, shoot and gather (the texture work
// timed apart); then, on the shot solution at 512 x 512, re-textures with another bump
// function at the scene's own quality and as drafts (draft_camera: one ray a pixel, one
// shadow ray): the first render of a SolutionView (which finds what no bump changes) and
// the mean of 10 after it, the memory it keeps, and whether those images equal a fresh
// render's.
#include <cstdio>
#include <string>
#include <vector>

#include "common/stopwatch.h"
#include "protocol/scene_source.h"
#include "solver/solution.h"

namespace {

using namespace bumprad;

void retexture(const char* label, Scene scene, const Solution& solution) {
  scene.camera.width = scene.camera.height = 512;
  std::vector<BumpFunction> other = scene.bumps;
  other[0].type = other[0].type == BumpType::Dimples ? BumpType::Noise : BumpType::Dimples;
  auto t0 = Clock::now();
  const SolutionView view(scene, solution);
  view.render(scene.bumps);
  const double first = seconds_since(t0);
  auto t1 = Clock::now();
  Image image;
  for (int i = 0; i < 10; ++i) image = view.render(i % 2 ? scene.bumps : other);
  const double again = seconds_since(t1) / 10;
  // The last of the ten (i = 9) had the scene's own bump functions.
  const bool same = image.rgb == render(scene, solution).rgb;
  std::printf(
      "  re-texture %-7s first %7.1f ms, then %6.1f ms  (keeps %.1f MB; %s a fresh render)\n",
      label, 1e3 * first, 1e3 * again, double(view.bytes()) / 1e6,
      same ? "same as" : "DIFFERENT FROM");
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> sources(argv + 1, argv + argc);
  if (sources.empty()) sources = {"builtin:paper-room", "builtin:wrinkled-box"};
  try {
    for (const std::string& source : sources) {
      Scene scene = load_scene(source);
      std::printf("%s (%d shots, hemi-cube %d)\n", source.c_str(), scene.solver.max_shots,
                  scene.solver.hemicube_resolution);
      std::printf("  %-8s %10s %10s %10s %9s\n", "texture", "total s", "solve s", "texture s",
                  "overhead");
      double plain = 0;
      for (TextureMode mode : {TextureMode::None, TextureMode::Shoot, TextureMode::Gather}) {
        scene.solver.texture = mode;
        auto t0 = Clock::now();
        Solution s = solve(scene);
        double total = seconds_since(t0);
        if (mode == TextureMode::None) plain = total;
        const char* name = mode == TextureMode::None    ? "none"
                           : mode == TextureMode::Shoot ? "shoot"
                                                        : "gather";
        std::printf("  %-8s %10.3f %10.3f %10.3f %8.1f%%  (%zu perturbed elements)\n", name, total,
                    s.stats.seconds_solve, s.stats.seconds_texture, 100 * (total - plain) / plain,
                    s.stats.perturbed_elements);
        if (mode != TextureMode::Shoot || scene.bumps.empty()) continue;
        retexture("full", scene, s);
        Scene draft = scene;
        draft.camera = draft_camera(draft.camera);
        retexture("draft", draft, s);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bumprad-bench-texture: %s\n", e.what());
    return 1;
  }
}
