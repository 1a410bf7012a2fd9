// A solved scene: mesh, radiosity and perturbed radiosity map, built in the scene's texture
// mode. Rendering takes a Scene too, so a new bump function or camera re-renders a solution
// without solving again (re-texturing, paper section 2.4).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stop_token>
#include <vector>

#include "solver/radiosity/near_field.h"
#include "solver/radiosity/perturbed_map.h"
#include "solver/radiosity/solve_stats.h"
#include "solver/radiosity/vertex_radiosity.h"
#include "solver/render/lights.h"
#include "solver/render/view_pass.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/util/image.h"

namespace bumprad {

struct Solution {
  std::unique_ptr<Mesh> mesh;
  std::vector<Rgb> radiosity;  // solved B per element
  std::vector<Rgb> display;    // B plus the ambient term, what images show
  // With DirectLight::Exact, the part of B straight from the emitters, per element; the
  // view pass computes it exactly instead, and the map holds the indirect light only.
  // Empty with DirectLight::Radiosity: the solution and the map hold all of it.
  std::vector<Rgb> direct;
  std::unique_ptr<PerturbedMap> map;  // null when no object is bumpy or the mode is none
  std::unique_ptr<RayScene> rays;
  OpenParts open;  // per element, open_parts(): how vertices weigh it, where light leaves
  // With DirectLight::Exact: the near sets the view pass puts back exactly (near_field.h).
  std::unique_ptr<NearField> near;
  SolveStats stats;
  // Adaptive subdivision: per level, the elements split (indices into that level's mesh).
  // build_mesh then these splits give the mesh back (refined_mesh).
  std::vector<std::vector<std::uint32_t>> refinements;
};

// Called after every refinement step with the snapshot and the solution as it stands: its
// mesh, rays and (when shooting) map are ready, so render(scene, solution, snapshot) is a
// preview with bumps from the first step on. Returning false stops
// the solve; the solution is then what was reached.
using StepCallback = std::function<bool(const Snapshot&, const Solution&)>;

// `stop` ends the solve mid-shot (a cancelled job): the solution is then partial and
// its map unfinished, and no final step is reported. With `refine_within_s`, a tolerance's
// extra adaptive levels (SolverSettings::tolerance) are taken only where the level before,
// scaled by the elements the next would have, says it ends within that many seconds of the
// solve's start (a job's time limit); 0: no limit.
Solution solve(const Scene& scene, const StepCallback& on_step = {}, std::stop_token stop = {},
               double refine_within_s = 0);

// The scene's mesh with a solution's refinements applied; throws std::invalid_argument if
// they do not fit it.
std::unique_ptr<Mesh> refined_mesh(const Scene& scene,
                                   const std::vector<std::vector<std::uint32_t>>& refinements);

// The (empty) perturbed map for `scene` on its mesh: null when no object has a bump
// function or the texture mode is none. Solving and loading a saved solution both use it.
std::unique_ptr<PerturbedMap> make_map(const Scene& scene, const Mesh& mesh);

// Fills the stats that describe the map (perturbed elements, directions) from `solution`.
void count_map_stats(const Scene& scene, Solution& solution);

// A solution seen by `scene`'s camera (the scene it was solved from, or one with other bump
// functions or another camera: the same geometry): the view pass, which keeps what no bump
// function changes, so render() again with other ones costs the shading alone. Objects
// without a bump function, or a solution without a map, render smooth. Direct light is
// exact per pixel where the solution has `direct`. The solution must outlive it. With
// `keep` false it is for one image (ViewPass).
class SolutionView {
 public:
  SolutionView(const Scene& scene, const Solution& solution, bool keep = true);
  // The same for one refinement step (previews).
  SolutionView(const Scene& scene, const Solution& solution, const Snapshot& step,
               bool keep = true);
  // The image with these bump functions (`scene`'s, or ones in their place). `stop` ends it
  // within a row; the image is then unfinished.
  Image render(std::span<const BumpFunction> bumps, std::stop_token stop = {}) const;
  // The memory it keeps, in bytes.
  std::size_t bytes() const;
  const Camera& camera() const { return camera_; }

 private:
  SolutionView(const Scene& scene, const Solution& solution, std::span<const Rgb> radiosity,
               std::span<const Rgb> direct, bool keep);
  Camera camera_;
  std::vector<Material> materials_;
  std::vector<Rgb> reflected_;
  std::optional<Lights> lights_;
  std::unique_ptr<ViewPass> view_;
};

// All of the light at the mesh's vertices (the displayed radiosity, direct light included),
// as the view pass interpolates it (vertex_values): what an exported model carries.
std::vector<Rgb> vertex_light(const Scene& scene, const Solution& solution);

// The perturbed map's values (slot * basis size + value, as PerturbedMap::values) for all of
// the light: what an exported model carries. With radiosity direct light they are the map's
// own. With exact direct light the map holds the indirect light (the view pass adds the
// direct light per pixel), so each slot adds its vertex's direct light at every N' from its
// shadow rays (Lights::direct_sources): each lamp's clipped form factor projected into the
// basis (MapBasis::project_polygon), each punctual light's clamped cosine, times the
// reflectance. Needs solution.map.
std::vector<Rgb> map_light(const Scene& scene, const Solution& solution);

// The rays a pixel across `solution`'s images use: the camera's, or more where a tolerance
// chose them (SolveStats::antialias).
int rendered_antialias(const Scene& scene, const Solution& solution);

// One image: SolutionView(scene, solution, false).render(scene.bumps, stop).
Image render(const Scene& scene, const Solution& solution, std::stop_token stop = {});
// The same for one refinement step (previews).
Image render(const Scene& scene, const Solution& solution, const Snapshot& step,
             std::stop_token stop = {});

}  // namespace bumprad
