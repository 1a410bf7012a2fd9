// The bookkeeping of progressive refinement: per element the radiosity B, the unshot dB (and
// the part of it that is the element's own emission), the part of B straight from the
// emitters; per patch its unshot power; per non-diffuse element its specular queue; the
// energy ledger, and the ambient term that both overshooting and previews use. Shots take
// power from here and deliver it back; nothing here knows how form factors are found.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "solver/radiosity/visible_element.h"
#include "solver/scene/mesh.h"
#include "solver/scene/scene.h"

namespace bumprad {

// Power bookkeeping in watts per channel. At every shot, emitted == absorbed + escaped +
// unshot up to rounding; `escaped` is what left an open scene through the hemi-cube's
// empty pixels.
struct EnergyLedger {
  Rgb emitted{0}, absorbed{0}, escaped{0}, unshot{0};
};

inline double channel_sum(const Rgb& c) {
  return c.r + c.g + c.b;
}

// Specular power queued at a non-diffuse element by the patch it came from. `emission` is
// the part that is an emitter's own emission meeting a planar mirror: its reflection is
// direct light (the emitter's image; Lights::direct computes it exactly).
struct Queued {
  std::uint32_t source;
  Rgb power, emission;
};

// What a patch shoots: its elements' unshot power (and what it sends ahead), the part of it
// that is their own emission, their specular queues merged by source, and the power each
// element shoots from its open part (channel sum, in magnitude), which says where the patch
// shoots from and how its near field is weighted.
struct Shooting {
  std::uint32_t patch;
  Rgb power{0}, emission{0};
  std::vector<Queued> sources;
  std::vector<double> weight;  // per element of the patch
};

// Light arriving at an element in one shot, for deliver().
struct Arrival {
  std::uint32_t element;
  Rgb incident;  // watts
  Rgb emission;  // the part of it that is an emitter's own emission (or its mirror image)
};

class Residuals {
 public:
  // `open`: per element, the share of its area open to the scene (vertex_radiosity.h's
  // open_share; empty: all open). Light is never sent ahead to buried parts.
  Residuals(const Mesh& mesh, const std::vector<Material>& materials, std::span<const double> open);

  // The patch with the largest unshot power in magnitude, none when nothing is left.
  std::optional<std::uint32_t> next_patch() const;
  // A patch's unshot power (channel sum, watts; negative: shot ahead).
  double unshot_power(std::uint32_t patch) const { return patch_unshot_power_[patch]; }
  // Takes the patch's unshot power for a shot, and what it is yet to receive, sent ahead
  // (overshooting; see the definition).
  Shooting take(std::uint32_t patch);
  // The diffuse shot's light: power * F to each element the shooter reaches, the rest
  // escaping.
  void deliver(const Shooting& shot, std::span<const VisibleElement> form_factors);
  // The punctual lights' light (no patch shot it): `emitted` joins the ledger, `escaped` is
  // what met no element's front. All of it is direct light. Its diffuse part is reflected; a
  // specular part is not queued (a point has no hemi-cube to reflect it from) and counts as
  // absorbed, except `reflected`: what planar mirrors sent on as the lights' images, which
  // `arrivals` include.
  void shine(std::span<const Arrival> arrivals, const Rgb& emitted, const Rgb& escaped,
             const Rgb& reflected);
  // Specular transfer's light, reflected by patch `source`, and what of it escaped.
  void deliver(std::uint32_t source, std::span<const Arrival> arrivals, const Rgb& escaped);

  // Sum of |unshot power| over patches / emitted power.
  double unshot_fraction() const;
  const std::vector<Rgb>& radiosity() const { return radiosity_; }
  const std::vector<Rgb>& direct() const { return direct_; }
  // B_i + rho_i * ambient (see ambient()).
  std::vector<Rgb> display_radiosity() const;
  EnergyLedger ledger() const;
  std::span<const Rgb> reflectance() const { return reflectance_; }
  std::span<const double> open() const { return open_; }

 private:
  Rgb unshot_power() const;
  // Radiosity per unit reflectance still to arrive at an average element (display term,
  // overshooting).
  Rgb ambient() const;
  // Element i receives `incident` watts from patch `source`: diffuse and specular shares;
  // `emission` of it is the source's own emission, straight from it.
  void receive(std::uint32_t element, const Rgb& incident, std::uint32_t source,
               const Rgb& emission = Rgb(0));

  const Mesh& mesh_;
  std::vector<Rgb> reflectance_;     // per element: diffuse albedo, element_reflectance()
  std::vector<double> open_;         // per element: share open to the scene
  std::vector<double> specular_;     // per element: k_s
  std::vector<bool> planar_mirror_;  // per surface, planar_mirrors()
  // Per non-diffuse element, the power it will reflect specularly, by source patch, since
  // its patch last shot (the paper's irradiation queues). Memory: one entry per source that
  // shot at it since then, so O(non-diffuse elements x sources per interval).
  std::vector<std::vector<Queued>> queue_;
  std::vector<Rgb> radiosity_;              // B, per element
  std::vector<Rgb> unshot_;                 // dB, per element
  std::vector<Rgb> unshot_emission_;        // the part of dB that is the element's own E
  std::vector<Rgb> direct_;                 // per element, see ProgressiveSolver::direct()
  std::vector<double> patch_unshot_power_;  // A * (dB.r + dB.g + dB.b), per patch
  Rgb emitted_{0}, absorbed_{0}, escaped_{0};
  Rgb mean_reflectance_{0};  // area-weighted
  // Reflected (not emitted) power shot so far, and the part of it that left the scene:
  // channel sums, for the ambient term's escape fraction.
  double reflected_shot_ = 0, reflected_escaped_ = 0;
  double total_area_ = 0;
};

}  // namespace bumprad
