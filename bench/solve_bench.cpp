// Solve benchmark: per-shot cost split into item-buffer rendering, pixel accumulation and
// the rest (shooter choice, near-field and aliasing corrections, distribution).
//   build/bin/bumprad-bench-solve [SCENE] [--shots N] [--hemicube R] [--element-size S]
//                                 [--patch-elements K] [--unshot F]
// SCENE defaults to builtin:paper-room. Without --unshot the whole shot budget is spent;
// with it the solve stops at that unshot fraction, as a job does. The numbers go in the
// README with the machine.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "common/args.h"
#include "common/stopwatch.h"
#include "protocol/scene_source.h"
#include "solver/radiosity/progressive.h"
#include "solver/radiosity/vertex_radiosity.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"

namespace {

struct Summary {
  double mean, median, p95;
};

Summary summarize(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  double sum = 0;
  for (double x : v) sum += x;
  return {sum / double(v.size()), v[v.size() / 2], v[std::min(v.size() - 1, v.size() * 95 / 100)]};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace bumprad;
  std::string source = "builtin:paper-room";
  int shots = -1, hemicube = -1, patch_elements = 0;
  double element_size = 0, unshot = 0;
  std::vector<std::string> positional;
  ArgParser()
      .integer({"--shots"}, shots, 1, 100'000'000)
      .integer({"--hemicube"}, hemicube, 2, 4096)
      .number({"--element-size"}, element_size, 0, 1e300)
      .integer({"--patch-elements"}, patch_elements, 1, 1024)
      .number({"--unshot"}, unshot, 0, 1)
      .positional(positional, 1)
      .parse_or_exit(argc, argv,
                     "usage: bumprad-bench-solve [SCENE] [--shots N] [--hemicube R] "
                     "[--element-size S] [--patch-elements K] [--unshot F]\n");
  if (!positional.empty()) source = positional.front();
  try {
    Scene scene = load_scene(source);
    if (shots > 0) scene.solver.max_shots = shots;
    if (hemicube > 0) scene.solver.hemicube_resolution = hemicube;
    if (element_size > 0) scene.solver.element_size = element_size;
    if (patch_elements > 0) scene.solver.patch_elements = patch_elements;
    scene.solver.unshot_fraction = unshot;  // 0: spend the whole shot budget

    auto t0 = Clock::now();
    Mesh mesh = build_mesh(scene);
    // As solve() does: rays for the aliasing fallback (or ray-cast mode), open parts.
    RayScene rays(mesh);
    const OpenParts open = open_parts(mesh, rays);
    ProgressiveSolver solver(mesh, scene.materials, scene.solver, &rays, &open);
    double setup = seconds_since(t0);

    // Diffuse shots and shots that also carry specular transfer (mirrors, glossy) apart.
    std::vector<double> render, accumulate, rest, total, specular, specular_total;
    while (!solver.done() && solver.shoot()) {
      const ShotTiming& t = solver.last_shot();
      render.push_back(1e3 * t.render_s);
      accumulate.push_back(1e3 * t.accumulate_s);
      rest.push_back(1e3 * (t.total_s - t.render_s - t.accumulate_s - t.specular_s));
      total.push_back(1e3 * (t.total_s - t.specular_s));
      if (t.specular_s > 0) {
        specular.push_back(1e3 * t.specular_s);
        specular_total.push_back(1e3 * t.total_s);
      }
    }
    double solve = seconds_since(t0);

    std::printf("scene %s: %zu elements, %zu patches, hemi-cube %d, %d shots, %u threads\n",
                source.c_str(), mesh.elements.size(), mesh.patches.size(),
                scene.solver.hemicube_resolution, solver.shots(),
                std::thread::hardware_concurrency());
    std::printf("%-22s %9s %9s %9s\n", "per shot (ms)", "mean", "median", "p95");
    auto row = [](const char* name, const std::vector<double>& v) {
      Summary s = summarize(v);
      std::printf("%-22s %9.3f %9.3f %9.3f\n", name, s.mean, s.median, s.p95);
    };
    row("item-buffer render", render);
    row("pixel accumulation", accumulate);
    row("rest", rest);
    row("shot, without specular", total);
    Summary r = summarize(render), w = summarize(total);
    std::printf("shot without specular transfer / render: %.2f (mean)\n", w.mean / r.mean);
    if (!specular.empty()) {
      std::printf("%zu of %d shots also carried specular transfer:\n", specular.size(),
                  solver.shots());
      row("specular transfer", specular);
      row("such a whole shot", specular_total);
    }
    std::printf(
        "set-up %.3f s (mesh, rays, open shares, GL context, buffers); solve total %.3f s; "
        "unshot %.2f%%\n",
        setup, solve, 100 * solver.unshot_fraction());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bumprad-bench-solve: %s\n", e.what());
    return 1;
  }
}
