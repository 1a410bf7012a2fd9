// Progressive refinement radiosity (Cohen, Chen, Wallace & Greenberg 1988): the patch with
// the most unshot power shoots it through a hemi-cube to every element it sees, overshooting
// by the light it is yet to receive (Feda & Purgathofer 1992).
// Memory is O(elements): form factors live for one shot only.
#pragma once

#include <functional>
#include <future>
#include <span>
#include <stop_token>
#include <vector>

#include "solver/radiosity/hemicube.h"
#include "solver/radiosity/perturbed_map.h"
#include "solver/radiosity/ray_cast_form_factor.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/scene/scene.h"
#include "solver/util/random.h"

namespace bumprad {

// Power bookkeeping in watts per channel. At every shot, emitted == absorbed + escaped +
// unshot up to rounding; `escaped` is what left an open scene through the hemi-cube's
// empty pixels.
struct EnergyLedger {
  Rgb emitted{0}, absorbed{0}, escaped{0}, unshot{0};
};

struct ShotTiming {
  double render_s = 0, accumulate_s = 0, texture_s = 0, specular_s = 0, total_s = 0;
};

// A finished (or stopped) solve, as reported to users.
struct SolveStats {
  int shots = 0;
  std::size_t elements = 0;
  double seconds_solve = 0;  // wall time, hemi-cube set-up included, texture work excluded
  double unshot_fraction = 0;
  double seconds_texture = 0;  // building the perturbed map (gather pass or shooting)
  // With SolverSettings::tolerance: the image's estimated relative RMS error against ground
  // truth and its standard error (error_estimate.h); 0 when not estimated.
  double estimated_error = 0, estimated_error_se = 0;
  std::size_t perturbed_elements = 0;
  std::size_t map_values = 0;            // numbers a map vertex stores per channel
  std::size_t non_diffuse_elements = 0;  // with a specular fraction
};

// What a refinement step hands out: enough to render a preview.
struct Snapshot {
  int shots = 0;
  double unshot_fraction = 0;
  bool final = false;
  std::vector<Rgb> radiosity;  // per element, with the ambient term for display
  std::vector<Rgb> direct;     // per element, the part of it straight from the emitters
};

class ProgressiveSolver {
 public:
  // `rays` (over the same mesh) serves ray-cast form factors and the hemi-cube's aliasing
  // fallback; without it, ray-cast settings are refused and the fallback is off. `open`
  // (per element, vertex_radiosity.h's open_share; empty: all open) keeps light from being
  // sent ahead to buried parts, which would never receive it.
  ProgressiveSolver(const Mesh& mesh, const std::vector<Material>& materials,
                    const SolverSettings& settings, const RayScene* rays = nullptr,
                    std::span<const double> open = {});

  // Every later shot also shoots into `map` (TextureMode::Shoot); null detaches it.
  void attach_map(PerturbedMap* map);

  // One shot from the patch with the largest unshot power in magnitude (negative: shot
  // ahead). False if nothing was left to shoot.
  bool shoot();
  // True once the shot budget is spent or unshot power is below the threshold.
  bool done() const;
  // A new unshot-power threshold: run() then goes on to it.
  void set_unshot_target(double fraction) { settings_.unshot_fraction = fraction; }
  // Shoots until done(); calls on_step after every `preview_every` shots and at the end.
  // on_step returning false stops the solve early; so does `stop`, checked after every
  // shot (a cancelled job stops within one shot). No final call is made after a stop.
  void run(const std::function<bool(const Snapshot&)>& on_step = {}, std::stop_token stop = {});

  int shots() const { return shots_; }
  // Sum of |unshot power| over patches / emitted power.
  double unshot_fraction() const;
  const std::vector<Rgb>& radiosity() const { return radiosity_; }
  // The part of B that came straight from the emitters' emission (rho E F, no bounce in
  // between) or from their images in planar mirrors (rho k_s E F): the view pass replaces it
  // with exact direct light (DirectLight::Exact).
  const std::vector<Rgb>& direct() const { return direct_; }
  // B_i + rho_i * ambient: Cohen 1988's estimate of the light not yet shot (diffuse and
  // queued specular), so early previews are not dark. It tends to zero as the solve
  // converges.
  std::vector<Rgb> display_radiosity() const;
  Snapshot snapshot() const;
  EnergyLedger ledger() const;
  const ShotTiming& last_shot() const { return last_shot_; }
  const ShotTiming& total_time() const { return total_; }

 private:
  Rgb unshot_power() const;
  // Radiosity per unit reflectance still to arrive at an average element (display term,
  // overshooting).
  Rgb ambient() const;
  double near_field_form_factor(std::uint32_t patch, const Vec3& origin, std::uint32_t element,
                                double hemicube_form_factor) const;
  // Where the patch shoots from: the centre of the power it shoots (see the definition).
  Vec3 shot_origin(std::uint32_t patch) const;
  // A point shadow rays sample on a patch: it stands for `share` of the patch's elements
  // [begin, end) (offsets in the patch).
  struct RaySample {
    Vec3 point;
    std::uint32_t begin, end;
    double share;
  };
  static std::vector<RaySample> ray_samples(const Mesh& mesh, const Patch& patch);
  void weigh_ray_samples(std::uint32_t patch);
  // F from the shooting patch to the element by rays (Wallace et al. 1989), exact where
  // near, the patch's parts weighed by the power they shoot.
  double ray_cast_form_factor_to(std::uint32_t patch, std::uint32_t element) const;
  // The shot's form factors: the hemi-cube's, corrected in the near field and where it
  // aliases, or all by rays.
  void find_form_factors(std::uint32_t patch, const Vec3& origin,
                         std::future<std::vector<VisibleElement>>* aliased);
  // The hemi-cube's aliasing receivers with their ray-cast form factors (see definition).
  std::vector<VisibleElement> aliased_form_factors(std::uint32_t patch) const;
  // Specular power queued at a non-diffuse element by the patch it came from. `emission` is
  // the part that is an emitter's own emission meeting a planar mirror: its reflection is
  // direct light (the emitter's image; Lights::direct computes it exactly).
  struct Queued {
    std::uint32_t source;
    Rgb power, emission;
  };
  static void add_by_source(std::vector<Queued>& list, const Queued& q);
  // Element i receives `incident` watts from patch `source`: diffuse and specular shares;
  // `emission` of it is the source's own emission, straight from it.
  void receive(std::uint32_t element, const Rgb& incident, std::uint32_t source,
               const Rgb& emission = Rgb(0));
  // The specular part of a shot (paper eq. 4-6): queued power per source, reflected by the
  // lobe from the source's pixels to the outgoing pixels of this hemi-cube.
  void shoot_specular(std::uint32_t patch, const Vec3& origin, const Frame& frame,
                      const std::vector<Queued>& sources);

  const Mesh& mesh_;
  SolverSettings settings_;
  const RayScene* rays_;
  std::vector<std::vector<AreaSample>> samples_;     // per patch: near field (quarter points)
  std::vector<std::vector<RaySample>> ray_samples_;  // per patch: shadow rays, kRaySamples
  // The shooting patch's area per element as it shoots, and its ray samples so weighed.
  std::vector<double> shot_area_;
  std::vector<AreaSample> shot_samples_;
  Hemicube hemicube_;
  std::vector<VisibleElement> visible_;     // the current shot's form factors
  std::vector<std::int32_t> visible_slot_;  // per element, its entry in visible_ or -1
  std::vector<Rgb> reflectance_;            // per element: diffuse albedo, element_reflectance()
  std::vector<double> open_;                // per element: share open to the scene
  std::vector<double> specular_;            // per element: k_s
  std::vector<double> shininess_;           // per element: Phong exponent, 0 for a mirror
  // Per non-diffuse element, the power it will reflect specularly, by source patch, since
  // its patch last shot (the paper's irradiation queues). Memory: one entry per source that
  // shot at it since then, so O(non-diffuse elements x sources per interval).
  std::vector<std::vector<Queued>> queue_;
  // The power each of the shooting patch's elements shoots from its open part (channel
  // sum, in magnitude), for where the patch shoots from and how its near field is weighted.
  std::vector<double> shot_weight_;
  std::vector<bool> planar_patch_;          // per patch: all its elements share its normal
  std::vector<bool> planar_mirror_;         // per surface, planar_mirrors()
  std::vector<std::int32_t> source_slot_;   // per patch, scratch for shoot_specular
  std::vector<Rgb> incident_;               // per element, scratch for shoot_specular
  std::vector<Rgb> incident_emission_;      // the same, its part from emitters' images
  std::vector<Rgb> radiosity_;              // B, per element
  std::vector<Rgb> unshot_;                 // dB, per element
  std::vector<Rgb> unshot_emission_;        // the part of dB that is the element's own E
  std::vector<Rgb> direct_;                 // per element, see direct()
  std::vector<double> patch_unshot_power_;  // A * (dB.r + dB.g + dB.b), per patch
  Rgb emitted_{0}, absorbed_{0}, escaped_{0};
  Rgb mean_reflectance_{0};  // area-weighted
  // Reflected (not emitted) power shot so far, and the part of it that left the scene:
  // channel sums, for the ambient term's escape fraction.
  double reflected_shot_ = 0, reflected_escaped_ = 0;
  double total_area_ = 0;
  int shots_ = 0;
  MersenneTwister rng_;
  PerturbedMap* map_ = nullptr;
  ShotTiming last_shot_, total_;
};

}  // namespace bumprad
