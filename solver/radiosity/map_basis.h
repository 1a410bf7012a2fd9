// What the perturbed radiosity map stores per vertex and colour channel: a few numbers, each
// a linear function of the light arriving, from which B'(N') at any perturbed normal is a
// linear combination. Spherical harmonics of the incident light (the default) or the
// sampled perturbed normals of Chen & Wu 1990.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "solver/scene/scene.h"
#include "solver/util/math.h"

namespace bumprad {

// B'(N') = sum over terms of weight * value[index].
struct MapTerms {
  static constexpr std::size_t kMax = 18;
  int count = 0;
  std::array<std::uint32_t, kMax> index{};
  std::array<double, kMax> weight{};
};

class MapBasis {
 public:
  explicit MapBasis(const MapSettings& settings);

  std::size_t size() const { return size_; }
  MapBasisKind kind() const { return kind_; }

  // Each value's response to light arriving from local direction `w` (unit; z along N) in
  // units of radiosity times solid angle / pi, so that a source of radiosity B seen over
  // the pixel dw adds B dw / pi * out[k]. Sampled normals: max(0, N_s . w), the cosine at
  // each sample (eq. 17). Spherical harmonics: A_l Y_lm(w), the projection scaled by the
  // clamped cosine's coefficients (Ramamoorthi & Hanrahan 2001), so that evaluation needs
  // only Y_lm(N'). `out` has size() entries.
  void project(const Vec3& w, std::span<double> out) const;
  // The combination of values that gives B' at a local unit normal. Sampled normals:
  // linear in azimuth within a ring and in tilt between rings (N is ring 0); tilts beyond
  // the outer ring, and normals below the tangent plane, use the outer ring.
  MapTerms evaluate(const Vec3& normal) const;
  // Each value's response to a polygon of radiosity 1 seen from the origin (local
  // coordinates, any winding): the integral of project(w) dw / pi over its solid angle, so
  // that evaluation at N' gives the point-to-polygon form factor clipped to N''s plane (a
  // lamp's direct light at every tilt, also where N' cuts it), to the basis's own limits (in
  // harmonics bands 0-2 and 4 of it), by a quadrature of sub-triangles under 0.05 radians.
  void project_polygon(std::span<const Vec3> polygon, std::span<double> out) const;
  // The values of a radiosity that is the same at every normal (emission): all ones for
  // sampled normals, 1 / Y_00 in the constant harmonic.
  std::span<const double> constant() const { return constant_; }

  // Sampled normals only (empty otherwise), in the local frame (x = T, y = S, z = N): N
  // first, then each tilt ring's azimuths from +T toward +S (E, NE, N, NW, ... for 8).
  std::span<const Vec3> sample_directions() const { return directions_; }

 private:
  MapBasisKind kind_;
  std::size_t size_;
  std::vector<double> constant_;
  std::vector<double> tilts_;  // radians, ascending
  int azimuths_ = 0;
  std::vector<Vec3> directions_;
};

}  // namespace bumprad
