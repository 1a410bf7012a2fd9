#include "solver/solution.h"

#include <optional>

#include "common/stopwatch.h"
#include "solver/radiosity/progressive.h"
#include "solver/radiosity/vertex_radiosity.h"
#include "solver/render/error_estimate.h"
#include "solver/render/lights.h"
#include "solver/render/view_pass.h"
#include "solver/scene/planar_mirror.h"
#include "solver/scene/subdivision.h"
#include "solver/util/parallel.h"

namespace bumprad {
namespace {

// Shadow rays a map slot's direct light takes (map_light): a vertex is one point for the
// whole area around it, so it can afford more than a pixel's sample.
constexpr int kMapShadowRays = 64;

// What of a solution the light does not change: the mesh, its (empty) map, its rays, open
// shares and near sets. After a stop, partial.
Solution prepared(const Scene& scene, std::unique_ptr<Mesh> mesh, std::stop_token stop) {
  Solution out;
  out.mesh = std::move(mesh);
  out.map = make_map(scene, *out.mesh);
  out.rays = std::make_unique<RayScene>(*out.mesh);
  out.open = open_parts(*out.mesh, *out.rays, stop);
  if (scene.solver.direct_light == DirectLight::Exact && !stop.stop_requested())
    out.near = std::make_unique<NearField>(*out.mesh, *out.rays, out.open.share, stop);
  return out;
}

// The map gathered after the solve (TextureMode::Gather): a hemi-cube at each bumpy vertex.
void gather_map(const Scene& scene, Solution& out, std::stop_token stop) {
  Hemicube hemicube(*out.mesh, scene.solver.hemicube_resolution);
  // With exact direct light the map gathers the indirect light only: what the vertex sees
  // less the emitters' own emission.
  std::vector<Rgb> seen = out.display;
  if (scene.solver.direct_light == DirectLight::Exact)
    for (std::size_t i = 0; i < seen.size(); ++i)
      seen[i] -= scene.materials[std::size_t(out.mesh->elements[i].material)].emission;
  out.map->gather(scene.materials, seen, hemicube, stop);
}

// One progressive solve on a given mesh, with its map and rays. With a tolerance,
// `antialias` is what an earlier level chose (SolveStats::antialias) and `estimator` its
// traced pixels, made on the first level that estimates (the truth does not change with the
// mesh).
Solution solve_on(const Scene& scene, std::unique_ptr<Mesh> mesh_in, const StepCallback& on_step,
                  int antialias, std::optional<ErrorEstimator>& estimator, std::stop_token stop) {
  auto t0 = Clock::now();
  Solution out = prepared(scene, std::move(mesh_in), stop);
  out.stats.antialias = antialias;
  if (stop.stop_requested()) return out;
  const Mesh& mesh = *out.mesh;
  const bool exact = scene.solver.direct_light == DirectLight::Exact;
  const TextureMode mode = out.map ? scene.solver.texture : TextureMode::None;

  ProgressiveSolver solver(mesh, scene.materials, scene.solver, out.rays.get(), &out.open, stop);
  solver.shine(punctual_sources(scene.lights, planar_mirror_planes(mesh, scene.materials)),
               *out.rays, stop);
  if (stop.stop_requested()) return out;
  out.stats.seconds_setup = seconds_since(t0);
  double texture_s = 0;
  if (mode == TextureMode::Shoot) solver.attach_map(out.map.get());
  const auto step = [&](const Snapshot& s) {
    if (!on_step) return true;
    if (mode == TextureMode::Shoot) {
      auto t = Clock::now();
      out.map->finish_shooting(scene.materials);
      texture_s += seconds_since(t);
    }
    return on_step(s, out);
  };
  const auto take = [&] {
    out.radiosity = solver.radiosity();
    out.display = solver.display_radiosity();
    if (exact) out.direct = solver.direct();
    out.stats.shots = solver.shots();
    out.stats.unshot_fraction = solver.unshot_fraction();
  };
  solver.run(step, stop);
  take();
  // A tolerance: estimate, and shoot on while that helps (the estimate falls by a tenth or
  // more a round); what no shot can lower is refined below (the pixels) and in solve() (the
  // mesh); the hemi-cube stays, and what it costs is reported. In gather mode the map comes
  // after the solve, so these rounds see the bumps flat.
  double estimate_s = 0;
  const auto estimate = [&] {
    auto t = Clock::now();
    if (!estimator) estimator.emplace(scene, mesh, *out.rays);
    const ErrorEstimate e = estimator->estimate(render(estimator->view(), out));
    estimate_s += seconds_since(t);
    out.stats.estimated_error = e.relative_rms;
    out.stats.estimated_error_se = e.standard_error;
    return e.relative_rms;
  };
  const double tolerance = scene.solver.tolerance;
  for (double previous = 0; tolerance > 0 && !stop.stop_requested();) {
    if (mode == TextureMode::Shoot) out.map->finish_shooting(scene.materials);
    const double error = estimate();
    if (error <= tolerance || solver.shots() >= scene.solver.max_shots ||
        (previous > 0 && error > 0.9 * previous) || solver.unshot_fraction() <= 1e-4)
      break;
    previous = error;
    solver.set_unshot_target(solver.unshot_fraction() / 3);
    solver.run(step, stop);
    take();
  }
  if (stop.stop_requested()) return out;
  // What shots cannot lower: first the pixels (at the Cornell box's defaults, 1.48 -> 1.33 %
  // from a 2,048-path reference with 4 x 4 rays a pixel for a view pass 2-3 times as long);
  // solve() then refines the mesh.
  if (tolerance > 0 && out.stats.estimated_error > tolerance &&
      std::max(scene.camera.antialias, out.stats.antialias) < SolverSettings::kToleranceAntialias) {
    out.stats.antialias = SolverSettings::kToleranceAntialias;
    estimate();
  }

  auto t1 = Clock::now();
  if (mode == TextureMode::Shoot) {
    out.map->finish_shooting(scene.materials);
  } else if (mode == TextureMode::Gather) {
    gather_map(scene, out, stop);
    if (stop.stop_requested()) return out;
  }
  texture_s += seconds_since(t1) + solver.total_time().texture_s;
  // The rounds above saw the bumps flat in gather mode (the map is gathered only now):
  // report the image as it will be rendered.
  if (scene.solver.tolerance > 0 && mode == TextureMode::Gather) estimate();

  out.stats.elements = mesh.elements.size();
  for (const Element& e : mesh.elements)
    out.stats.non_diffuse_elements += scene.materials[std::size_t(e.material)].specular > 0;
  out.stats.seconds_texture = texture_s;
  out.stats.seconds_solve = seconds_since(t0) - texture_s - estimate_s;
  count_map_stats(scene, out);
  return out;
}

}  // namespace

std::unique_ptr<Mesh> refined_mesh(const Scene& scene,
                                   const std::vector<std::vector<std::uint32_t>>& refinements) {
  auto mesh = std::make_unique<Mesh>(build_mesh(scene));
  for (const auto& split : refinements) {
    for (std::uint32_t i : split)
      if (i >= mesh->elements.size())
        throw std::invalid_argument("a refinement names element " + std::to_string(i) +
                                    " of a mesh of " + std::to_string(mesh->elements.size()));
    mesh = std::make_unique<Mesh>(subdivide(*mesh, split));
  }
  return mesh;
}

// Adaptive subdivision: solve, split where neighbours differ, solve the finer mesh again,
// up to adaptive_levels times, and a tolerance's levels after those (scene.h). Each level is
// a whole progressive solve; the step callback sees them all.
Solution solve(const Scene& scene, const StepCallback& on_step, std::stop_token stop,
               double refine_within_s) {
  auto t0 = Clock::now();
  std::vector<std::vector<std::uint32_t>> refinements;
  auto mesh = std::make_unique<Mesh>(build_mesh(scene, stop));
  double setup = seconds_since(t0);
  if (stop.stop_requested()) {
    Solution out;
    out.mesh = std::move(mesh);
    out.stats.seconds_setup = setup;
    return out;
  }
  const SolverSettings& settings = scene.solver;
  int antialias = 0;
  std::optional<ErrorEstimator> estimator;
  std::optional<Solution> coarser;  // the level a tolerance's level refines
  for (int level = 0;; ++level) {
    const auto level_start = Clock::now();
    Solution out = solve_on(scene, std::move(mesh), on_step, antialias, estimator, stop);
    const double level_s = seconds_since(level_start);
    setup += out.stats.seconds_setup;
    out.stats.seconds_setup = setup;
    out.refinements = refinements;
    antialias = out.stats.antialias;
    const auto finished = [&](Solution& s) {
      s.stats.seconds_setup = setup;
      s.stats.seconds_solve = seconds_since(t0) - s.stats.seconds_texture;
      return std::move(s);
    };
    // A tolerance the shots and pixels could not meet refines the mesh further, while each
    // level lowers the estimate by a tenth. A level that does not lower it at all gives way
    // to the one it refined (paper-room at a tolerance of 1 %: its first level estimated
    // 3.8 +- 0.8 %, where the coarser mesh's shots had stopped).
    const double error = out.stats.estimated_error;
    if (coarser && !(error < coarser->stats.estimated_error)) return finished(*coarser);
    const bool tolerated = settings.tolerance > 0 && error > settings.tolerance &&
                           level < settings.adaptive_levels + SolverSettings::kToleranceLevels &&
                           (!coarser || error < 0.9 * coarser->stats.estimated_error);
    std::vector<std::uint32_t> split;
    if ((level < settings.adaptive_levels || tolerated) && !stop.stop_requested())
      split = elements_to_split(*out.mesh, out.display, settings.adaptive_threshold);
    const std::size_t elements = out.mesh->elements.size(), next = elements + 3 * split.size();
    if (level >= settings.adaptive_levels && refine_within_s > 0 &&
        seconds_since(t0) + level_s * double(next) / double(elements) > refine_within_s)
      split.clear();  // the tolerance's level would not end in time
    if (split.empty() || next > std::size_t(Limits::kMaxElements)) return finished(out);
    refinements.push_back(split);
    const auto t = Clock::now();
    mesh = std::make_unique<Mesh>(subdivide(*out.mesh, split));
    setup += seconds_since(t);
    if (level >= settings.adaptive_levels && settings.tolerance > 0) coarser = std::move(out);
  }
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
  solution.stats.map_values = 0;
  if (!solution.map) return;
  for (const Element& e : solution.mesh->elements)
    solution.stats.perturbed_elements += scene.objects[e.object].bump >= 0;
  solution.stats.map_values = solution.map->basis().size();
}

// `radiosity` per element as displayed; `direct` its part straight from the emitters, or
// empty (then all light comes from the solution).
SolutionView::SolutionView(const Scene& scene, const Solution& solution,
                           std::span<const Rgb> radiosity, std::span<const Rgb> direct, bool keep)
    : camera_(scene.camera), materials_(scene.materials) {
  camera_.antialias = rendered_antialias(scene, solution);
  SurfaceDetail detail;
  detail.map = solution.map.get();
  for (const Object& o : scene.objects) detail.object_bump.push_back(o.bump);
  detail.materials = materials_;
  detail.open = solution.open.share;
  if (direct.empty()) {
    view_ = std::make_unique<ViewPass>(*solution.mesh, *solution.rays, camera_, radiosity, detail,
                                       keep);
    return;
  }
  std::vector<Rgb> indirect(radiosity.begin(), radiosity.end());
  for (std::size_t i = 0; i < indirect.size(); ++i) indirect[i] -= direct[i];
  lights_.emplace(*solution.mesh, materials_, scene.lights);
  detail.lights = &*lights_;
  reflected_.assign(radiosity.begin(), radiosity.end());
  for (std::size_t i = 0; i < reflected_.size(); ++i)
    reflected_[i] -= materials_[std::size_t(solution.mesh->elements[i].material)].emission;
  detail.near = solution.near.get();
  detail.reflected = reflected_;
  view_ =
      std::make_unique<ViewPass>(*solution.mesh, *solution.rays, camera_, indirect, detail, keep);
}

std::vector<Rgb> vertex_light(const Scene& scene, const Solution& solution) {
  SurfaceDetail detail;
  detail.materials = scene.materials;
  detail.open = solution.open.share;
  return vertex_values(*solution.mesh, solution.display, detail);
}

std::vector<Rgb> map_light(const Scene& scene, const Solution& solution) {
  const PerturbedMap& map = *solution.map;
  const Mesh& mesh = *solution.mesh;
  const MapBasis& basis = map.basis();
  const std::size_t n = basis.size();
  std::vector<Rgb> out(map.vertex_count() * n);
  for (std::uint32_t s = 0; s < map.vertex_count(); ++s)
    std::ranges::copy(map.values(s), out.begin() + std::ptrdiff_t(s * n));
  if (solution.direct.empty()) return out;
  // Each slot's reflectance (area-weighted over the bumpy elements at its vertex, as the
  // map's own values are) and a normal for a vertex whose elements' normals cancel.
  std::vector<Rgb> reflectance(map.vertex_count(), Rgb(0));
  std::vector<double> area(map.vertex_count(), 0);
  std::vector<Vec3> fallback(map.vertex_count(), Vec3(0, 0, 1));
  for (const Element& e : mesh.elements) {
    if (scene.objects[e.object].bump < 0) continue;
    for (int k = 0; k < e.vertex_count; ++k) {
      const std::int32_t s = map.slot(e.v[std::size_t(k)]);
      if (s < 0) continue;
      reflectance[std::size_t(s)] += e.area * scene.materials[std::size_t(e.material)].reflectance;
      area[std::size_t(s)] += e.area;
      fallback[std::size_t(s)] = e.normal;
    }
  }
  const Lights lights(mesh, scene.materials, scene.lights);
  parallel_for(int(map.vertex_count()), [&](int i) {
    const auto s = std::uint32_t(i);
    if (!(area[s] > 0)) return;
    const Vertex& v = mesh.vertices[map.vertex_of(s)];
    const Vec3 normal = glm::length(v.normal) > 0.5 ? glm::normalize(v.normal) : fallback[s];
    const Frame frame = tangent_frame(normal, v.dpdu);
    const Rgb rho = reflectance[s] / area[s];
    std::vector<double> values(n);
    std::vector<Vec3> local;
    lights.direct_sources(
        v.position, normal, *solution.rays, ShadowRays{kMapShadowRays},
        [&](const Rgb& weight, const Vec3& toward, std::span<const Vec3> polygon) {
          if (polygon.empty()) {
            basis.project(frame.to_local(toward), values);
          } else {
            local.clear();
            for (const Vec3& c : polygon) local.push_back(frame.to_local(c - v.position));
            basis.project_polygon(local, values);
          }
          for (std::size_t t = 0; t < n; ++t) out[s * n + t] += rho * weight * values[t];
        });
  });
  return out;
}

SolutionView::SolutionView(const Scene& scene, const Solution& solution, bool keep)
    : SolutionView(scene, solution, solution.display, solution.direct, keep) {}

SolutionView::SolutionView(const Scene& scene, const Solution& solution, const Snapshot& step,
                           bool keep)
    : SolutionView(scene, solution, step.radiosity,
                   scene.solver.direct_light == DirectLight::Exact
                       ? std::span<const Rgb>(step.direct)
                       : std::span<const Rgb>(),
                   keep) {}

Image SolutionView::render(std::span<const BumpFunction> bumps, std::stop_token stop) const {
  return view_->render(bumps, stop);
}

std::size_t SolutionView::bytes() const {
  return view_->bytes() + reflected_.capacity() * sizeof(Rgb);
}

int rendered_antialias(const Scene& scene, const Solution& solution) {
  return std::max(scene.camera.antialias, solution.stats.antialias);
}

Image render(const Scene& scene, const Solution& solution, std::stop_token stop) {
  return SolutionView(scene, solution, false).render(scene.bumps, stop);
}

Image render(const Scene& scene, const Solution& solution, const Snapshot& step,
             std::stop_token stop) {
  return SolutionView(scene, solution, step, false).render(scene.bumps, stop);
}

}  // namespace bumprad
