// Progressive refinement radiosity (Cohen, Chen, Wallace & Greenberg 1988): the patch with
// the most unshot power shoots it through a hemi-cube to every element it sees, overshooting
// by the light it is yet to receive (Feda & Purgathofer 1992). A shot takes its power from
// the bookkeeping (residuals.h), finds its form factors (shot_form_factors.h), reflects its
// specular queues (specular_transfer.h) and shoots into the perturbed map. A small round
// object's patches shoot together, as a cluster (clusters.h).
// Memory is O(elements): form factors live for one shot only.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <stop_token>
#include <vector>

#include "common/stopwatch.h"
#include "solver/radiosity/clusters.h"
#include "solver/radiosity/hemicube.h"
#include "solver/radiosity/residuals.h"
#include "solver/radiosity/shot_form_factors.h"
#include "solver/radiosity/solve_stats.h"
#include "solver/radiosity/specular_transfer.h"
#include "solver/radiosity/vertex_radiosity.h"
#include "solver/scene/mesh.h"
#include "solver/scene/punctual_light.h"
#include "solver/scene/ray_scene.h"
#include "solver/scene/scene.h"
#include "solver/util/random.h"

namespace bumprad {

class PerturbedMap;

class ProgressiveSolver {
 public:
  // `rays` (over the same mesh) serves ray-cast form factors and the hemi-cube's aliasing
  // fallback; without it, ray-cast settings are refused and the fallback is off. `open`
  // (vertex_radiosity.h's open_parts; null: all open) keeps light from being sent ahead to
  // buried parts, which would never receive it, and says where a partly buried element's
  // light leaves from. A stop requested while it is built (or while shine() runs) leaves a
  // solver that must not shoot: its caller returns.
  ProgressiveSolver(const Mesh& mesh, const std::vector<Material>& materials,
                    const SolverSettings& settings, const RayScene* rays = nullptr,
                    const OpenParts* open = nullptr, std::stop_token stop = {});

  // The punctual lights' light and their images' in planar mirrors (punctual_sources()),
  // before any patch shoots: per element the mean of punctual_irradiance() over its four
  // quarter points.
  void shine(std::span<const PunctualSource> lights, const RayScene& rays,
             std::stop_token stop = {});

  // Every later shot also shoots into `map` (TextureMode::Shoot); null detaches it.
  void attach_map(PerturbedMap* map);

  // One shot from the patch with the largest unshot power in magnitude (negative: shot
  // ahead), or from a cluster (clusters.h) whose patches hold more together, or that holds
  // that patch: all its patches shoot, and it counts one shot. False if nothing was left to shoot,
  // or if `stop` ended it: its loops (near field, aliasing rays, specular transfer, the map's
  // shoot) check it, and a stopped shot's power is lost, so the solver is then good for its
  // statistics only.
  bool shoot(std::stop_token stop = {});
  // True once the shot budget is spent or unshot power is below the threshold.
  bool done() const;
  // A new unshot-power threshold: run() then goes on to it.
  void set_unshot_target(double fraction) { settings_.unshot_fraction = fraction; }
  // Shoots until done(); calls on_step after every `preview_every` shots and at the end.
  // on_step returning false stops the solve early; so does `stop`, checked within every
  // shot (see shoot()). No final call is made after a stop.
  void run(const std::function<bool(const Snapshot&)>& on_step = {}, std::stop_token stop = {});

  int shots() const { return shots_; }
  // Sum of |unshot power| over patches / emitted power.
  double unshot_fraction() const { return residuals_.unshot_fraction(); }
  const std::vector<Rgb>& radiosity() const { return residuals_.radiosity(); }
  // The part of B that came straight from the emitters' emission (rho E F, no bounce in
  // between) or from their images in planar mirrors (rho k_s E F): the view pass replaces it
  // with exact direct light (DirectLight::Exact).
  const std::vector<Rgb>& direct() const { return residuals_.direct(); }
  // B_i + rho_i * ambient: Cohen 1988's estimate of the light not yet shot (diffuse and
  // queued specular), so early previews are not dark. It tends to zero as the solve
  // converges.
  std::vector<Rgb> display_radiosity() const { return residuals_.display_radiosity(); }
  Snapshot snapshot() const;
  EnergyLedger ledger() const { return residuals_.ledger(); }
  const ShotTiming& last_shot() const { return last_shot_; }
  const ShotTiming& total_time() const { return total_; }

 private:
  // Where the patch shoots from: the centre of the power it shoots (see the definition).
  Vec3 shot_origin(const Shooting& shot) const;
  // The cluster that shoots next instead of the patch `next`, if any.
  const Cluster* cluster_shooting(std::uint32_t next) const;
  bool shoot(const Cluster& cluster, std::stop_token stop);
  // The power a shot gives the perturbed map: with exact direct light the map holds the
  // indirect light only, so an emitter's own emission is left out.
  Rgb mapped_power(const Shooting& shooting) const;
  // Books a shot's time, from t0 and the hemi-cube's totals before it.
  void time_shot(Clock::time_point t0, const ShotTiming& hemicube_before, double texture_s,
                 double specular_s);

  const Mesh& mesh_;
  SolverSettings settings_;
  Residuals residuals_;
  std::unique_ptr<ShotFormFactors> form_factors_;
  SpecularTransfer specular_;
  Hemicube hemicube_;
  std::vector<bool> curved_patch_;  // per patch: curved() (geometry.h)
  std::vector<Cluster> clusters_;
  std::vector<std::int32_t> cluster_of_;  // per patch: its cluster in clusters_, or -1
  const OpenParts* open_;                 // or null: all open
  int shots_ = 0;
  MersenneTwister rng_;
  PerturbedMap* map_ = nullptr;
  ShotTiming last_shot_, total_;
};

}  // namespace bumprad
