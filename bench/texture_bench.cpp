// Texture benchmark: the cost of the perturbed radiosity map, and of re-texturing.
//   build/bin/bumprad-bench-texture [SCENE...]      (default: paper-room and wrinkled-box)
// For each scene: the whole solve with texture none, shoot and gather (the texture work
// timed apart), and a 512 x 512 re-texture with another bump function (mean of 10).
#include <cstdio>
#include <string>
#include <vector>

#include "common/stopwatch.h"
#include "protocol/scene_source.h"
#include "solver/solution.h"

int main(int argc, char** argv) {
  using namespace bumprad;
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
        Scene retextured = scene;
        retextured.camera.width = retextured.camera.height = 512;
        retextured.camera.antialias = 1;
        retextured.bumps[0].type = BumpType::Dimples;
        render(retextured, s);  // warm
        auto t1 = Clock::now();
        for (int i = 0; i < 10; ++i) render(retextured, s);
        std::printf("  re-texture 512x512, 1 ray per pixel: %.1f ms\n",
                    1e3 * seconds_since(t1) / 10);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bumprad-bench-texture: %s\n", e.what());
    return 1;
  }
}
