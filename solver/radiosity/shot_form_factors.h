// How a shot finds its form factors, from the shooting patch (or a cluster's centre) to
// every element it reaches: one interface, two methods. The hemi-cube's item buffer (Cohen &
// Greenberg 1985), corrected where it is known to fail: in the near field by Lambert's exact
// values, for receivers that fall between its pixels by rays; or shadow rays alone (Wallace,
// Elmquist & Haines 1989). A new method implements ShotFormFactors and joins
// make_shot_form_factors().
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <stop_token>
#include <vector>

#include "solver/radiosity/clusters.h"
#include "solver/radiosity/hemicube.h"
#include "solver/radiosity/vertex_radiosity.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/scene/scene.h"

namespace bumprad {

// The hemi-cube's near field: receivers closer than this many shooter sizes (the square
// root of the patch's area) take Lambert's values averaged over at most this many points
// of the shooter (solver/cost.cpp counts them).
constexpr double kNearFieldSizes = 3.0;
constexpr std::size_t kNearFieldPoints = 256;

// A shot as its form factors see it.
struct Shot {
  std::uint32_t patch;
  Vec3 origin;                     // where the hemi-cube sits, lifted off the surface
  std::span<const double> weight;  // per element of the patch: the power it shoots
  // Ends the shot's loops early (a cancelled or timed-out job); its form factors are then
  // incomplete and must not be delivered.
  std::stop_token stop = {};
};

class ShotFormFactors {
 public:
  virtual ~ShotFormFactors() = default;
  // Whether find() reads the shot's hemi-cube, which must then be rendered before it.
  virtual bool reads_hemicube() const = 0;
  // Starts a shot before its hemi-cube renders: what needs no item buffer may run meanwhile.
  virtual void begin(const Shot& shot) = 0;
  // F from the patch to each element it reaches (summing to at most 1). With `map`, the
  // hemi-cube's watched pixels are listed too (Hemicube::watch), whatever the method.
  virtual std::vector<VisibleElement>& find(const Shot& shot, Hemicube& hemicube, bool map) = 0;
  // A cluster's shot: per member (in cluster.patches' order), F to each element outside the
  // cluster, its light leaving the centre in the member's `lobes` (member_lobes()). The
  // hemi-cube, where read, is rendered here: both halves about `frame`, from the centre.
  virtual std::vector<std::vector<VisibleElement>> find(const Cluster& cluster,
                                                        std::span<const std::vector<Vec3>> lobes,
                                                        const Frame& frame, Hemicube& hemicube,
                                                        std::stop_token stop) = 0;
};

// The settings' method (SolverSettings::form_factors). `rays` (over the same mesh) serves
// ray casting and the hemi-cube's aliasing fallback: ray casting needs it, the fallback is
// off without it. `open`: per element, the share of its area open to the scene and where
// that part lies (vertex_radiosity.h's open_parts; null: all open). A `stop` cuts the set-up
// short (the caller then does not shoot).
std::unique_ptr<ShotFormFactors> make_shot_form_factors(const Mesh& mesh,
                                                        const SolverSettings& settings,
                                                        const RayScene* rays, const OpenParts* open,
                                                        std::stop_token stop = {});

}  // namespace bumprad
