// The specular part of a shot (paper eq. 4-6), the first of the two passes for non-diffuse
// scenes: the power queued at the shooting patch's mirror or glossy elements, by the patch it
// came from, leaves along the reflection of where it came in, through the Phong lobe, from
// the source's pixels of the shot's hemi-cube to the pixels it goes out through. It returns
// what arrives where; the solver's bookkeeping (residuals.h) takes it from there.
#pragma once

#include <cstdint>
#include <span>
#include <stop_token>
#include <vector>

#include "solver/radiosity/residuals.h"
#include "solver/scene/mesh.h"
#include "solver/scene/scene.h"
#include "solver/util/frame.h"

namespace bumprad {

class Hemicube;
class PerturbedMap;

class SpecularTransfer {
 public:
  SpecularTransfer(const Mesh& mesh, const std::vector<Material>& materials);

  struct Result {
    std::vector<Arrival> arrivals;  // per element reached, in the order first reached
    Rgb escaped{0};                 // watts that left the scene
  };
  // The queued power of `sources` reflected by patch `patch`, its hemi-cube rendered from
  // `origin` in `frame`. Rays also go into `map` when there is one, without the emitters'
  // images when `exact` (exact direct light: the view pass computes that light). `stop`
  // ends it between sources and within a source's pixels; what it returns then is partial.
  Result transfer(std::uint32_t patch, const Vec3& origin, const Frame& frame,
                  const Hemicube& hemicube, std::span<const Queued> sources, PerturbedMap* map,
                  bool exact, std::stop_token stop = {});

 private:
  static constexpr int kLobe = 32;  // lobe samples per incoming direction
  struct Pass;
  std::vector<std::vector<std::uint32_t>> source_pixels(std::span<const std::uint32_t> ids,
                                                        std::span<const Queued> sources);
  void deposit(Pass& pass, std::size_t pixel, const Rgb& power, const Rgb& emission);
  void reflect(Pass& pass, std::uint32_t pixel, const Rgb& power, const Rgb& emission, int count,
               int first);

  const Mesh& mesh_;
  std::vector<double> shininess_;          // per element: Phong exponent, 0 for a mirror
  std::vector<std::int32_t> source_slot_;  // per patch, scratch
  std::vector<Rgb> incident_;              // per element, scratch
  std::vector<Rgb> incident_emission_;     // the same, its part from emitters' images
};

}  // namespace bumprad
