#include "solver/solution.h"

#include "solver/stopwatch.h"
#include "solver/view_pass.h"

namespace bumprad {
namespace {}  // namespace

Solution solve(const Scene& scene, const StepCallback& on_step, std::stop_token stop) {
  auto t0 = Clock::now();
  Solution out;
  out.mesh = std::make_unique<Mesh>(build_mesh(scene));
  const Mesh& mesh = *out.mesh;

  out.map = make_map(scene, mesh);
  out.rays = std::make_unique<RayScene>(mesh);
  const TextureMode mode = out.map ? scene.solver.texture : TextureMode::None;

  ProgressiveSolver solver(mesh, scene.materials, scene.solver, out.rays.get());
  double texture_s = 0;
  if (mode == TextureMode::Shoot) solver.attach_map(out.map.get());
  solver.run(
      [&](const Snapshot& s) {
        if (!on_step) return true;
        if (mode == TextureMode::Shoot) {
          auto t = Clock::now();
          out.map->finish_shooting(scene.materials);
          texture_s += seconds_since(t);
        }
        return on_step(s, out);
      },
      stop);
  out.radiosity = solver.radiosity();
  out.display = solver.display_radiosity();
  out.stats.shots = solver.shots();
  out.stats.unshot_fraction = solver.unshot_fraction();
  if (stop.stop_requested()) return out;

  auto t1 = Clock::now();
  if (mode == TextureMode::Shoot) {
    out.map->finish_shooting(scene.materials);
  } else if (mode == TextureMode::Gather) {
    Hemicube hemicube(mesh, scene.solver.hemicube_resolution);
    out.map->gather(scene.materials, out.display, hemicube);
  }
  texture_s += seconds_since(t1) + solver.total_time().texture_s;

  out.stats.elements = mesh.elements.size();
  for (const Element& e : mesh.elements)
    out.stats.non_diffuse_elements += scene.materials[std::size_t(e.material)].specular > 0;
  out.stats.seconds_texture = texture_s;
  out.stats.seconds_solve = seconds_since(t0) - texture_s;
  count_map_stats(scene, out);
  return out;
}

std::unique_ptr<PerturbedMap> make_map(const Scene& scene, const Mesh& mesh) {
  std::vector<bool> bumpy;
  bool any = false;
  for (const Object& o : scene.objects) {
    bumpy.push_back(o.bump >= 0);
    any = any || o.bump >= 0;
  }
  if (!any || scene.solver.texture == TextureMode::None) return nullptr;
  return std::make_unique<PerturbedMap>(mesh, bumpy, scene.solver.map);
}

void count_map_stats(const Scene& scene, Solution& solution) {
  solution.stats.perturbed_elements = 0;
  solution.stats.directions = 0;
  if (!solution.map) return;
  for (const Element& e : solution.mesh->elements)
    solution.stats.perturbed_elements += scene.objects[e.object].bump >= 0;
  solution.stats.directions = solution.map->directions().size();
}

Image render(const Scene& scene, const Solution& solution) {
  return render(scene, solution, solution.display);
}

Image render(const Scene& scene, const Solution& solution, std::span<const Rgb> radiosity) {
  SurfaceDetail detail;
  detail.map = solution.map.get();
  detail.bumps = scene.bumps;
  for (const Object& o : scene.objects) detail.object_bump.push_back(o.bump);
  detail.materials = scene.materials;
  return render_view(*solution.mesh, *solution.rays, scene.camera, radiosity, detail);
}

}  // namespace bumprad
