// The perturbed radiosity map (Chen & Wu 1990, sections 2.2-2.4): for every vertex of a
// bumpy surface, the radiosity B'(N') at any perturbed normal, stored as a few numbers in a
// MapBasis. It depends on geometry and light only, so any bump function renders from it
// without solving again. Built by gathering after the solve (eq. 10, 13-19) or by shooting
// at every step (eq. 20-22).
#pragma once

#include <cstdint>
#include <span>
#include <stop_token>
#include <vector>

#include "solver/radiosity/hemicube.h"
#include "solver/radiosity/map_basis.h"
#include "solver/scene/mesh.h"
#include "solver/scene/scene.h"

namespace bumprad {

// A tangent frame (T, S, N) with N the unit normal and T along dpdu where it can be.
Frame tangent_frame(const Vec3& n, const Vec3& dpdu);

class PerturbedMap {
 public:
  // The vertices of elements whose object is marked in `perturbed_objects` get a slot.
  PerturbedMap(const Mesh& mesh, const std::vector<bool>& perturbed_objects,
               const MapSettings& settings);

  const MapBasis& basis() const { return basis_; }
  std::size_t vertex_count() const { return slot_vertex_.size(); }
  bool empty() const { return slot_vertex_.empty(); }
  // The map slot of a mesh vertex, or -1 when the vertex is not perturbed.
  std::int32_t slot(std::uint32_t vertex) const { return vertex_slot_[vertex]; }
  std::uint32_t vertex_of(std::uint32_t slot) const { return slot_vertex_[slot]; }
  // The basis's values of one slot.
  std::span<const Rgb> values(std::uint32_t slot) const;
  std::span<Rgb> values(std::uint32_t slot);
  // B'(N') of one slot for a normal's terms (MapBasis::evaluate).
  Rgb value(std::uint32_t slot, const MapTerms& terms) const;
  // B'(N') at a local unit normal.
  Rgb lookup(std::uint32_t slot, const Vec3& local) const;
  // The terms of the unperturbed normal N.
  const MapTerms& unperturbed() const { return unperturbed_; }

  // Post-process (eq. 10, 13-19): a hemi-cube at each perturbed vertex, whose pixels'
  // radiosity is projected into the basis (for sampled normals, B' = E + rho (N'.S -
  // shadowed sliver), S the radiosity-weighted directional sums of eq. 18-19). `radiosity`
  // is per element. `stop` ends it between vertices; the map is then unfinished.
  void gather(const std::vector<Material>& materials, std::span<const Rgb> radiosity,
              Hemicube& hemicube, std::stop_token stop = {});

  // Per mesh element: does it carry the map? (For Hemicube::watch before shooting.)
  std::vector<bool> perturbed_elements() const;

  // Shooting (eq. 20-22): call after every shot with the shooter's frame, its shot power
  // (dB_j A_j per channel) and the form factors the solver used, which carry its
  // near-field corrections; F'' is scaled by the same ratio per element. An element the
  // solver lit but the hemi-cube missed (ray-cast form factors, the aliasing fallback) is
  // lit as by one ray from the shooter's `origin`. The hemi-cube must watch
  // perturbed_elements(). `stop` ends it within its pixels, adding nothing of the shot.
  void shoot(const Hemicube& hemicube, const Frame& shooter, const Vec3& origin, const Rgb& power,
             std::span<const VisibleElement> used, std::stop_token stop = {});
  // Power arriving at a perturbed element along one direction (`to_source`, world, unit),
  // as specular transfer delivers it (paper section 2.4: texture lit by reflections).
  // Ignored for elements without the map.
  void receive_ray(std::uint32_t element, const Vec3& to_source, const Rgb& power);

  // Turns what shooting has accumulated into vertex values (area-weighted over the
  // elements around each vertex). Cheap; call before each preview.
  void finish_shooting(const std::vector<Material>& materials);

 private:
  const Mesh& mesh_;
  MapBasis basis_;
  MapTerms unperturbed_;
  bool self_illumination_;
  std::vector<std::int32_t> vertex_slot_;
  std::vector<std::uint32_t> slot_vertex_;
  std::vector<Rgb> values_;  // slot * basis size + value

  // Shooting state, per perturbed element.
  std::vector<std::int32_t> element_slot_;
  std::vector<std::uint32_t> slot_element_;
  std::vector<Frame> element_frames_;
  std::vector<Rgb> element_received_;  // element slot * basis size + value: incident light
  std::vector<double> scratch_;        // per element slot * (basis size + 1): F'' and F
  std::vector<double> projected_;      // one direction's MapBasis::project
  std::vector<std::uint32_t> touched_;
};

}  // namespace bumprad
