// Smooth shading of a radiosity solution: vertex values as the area-weighted mean of the
// adjacent elements (which share vertices only within a smooth surface), counting only the
// part of each element open to the scene, interpolated bilinearly inside quads and
// barycentrically inside triangles.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <stop_token>
#include <vector>

#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"

namespace bumprad {

// `open` (per element, from open_share; empty: all open) weights each element's area; the
// radiosity is then that of each element's open part.
std::vector<Rgb> vertex_radiosity(const Mesh& mesh, std::span<const Rgb> element_radiosity,
                                  std::span<const double> open = {});

// The share of each element's area open to the scene rather than buried under or inside
// other geometry (a floor under a block, a ceiling behind a lamp mounted on it). Buried
// parts get no light; averaged into a vertex they would darken the open elements beside
// them (at the Cornell box's block bases, 6 % too dark). A point is buried when most of five
// rays (along its normal and tilted 60 degrees four ways) meet back faces first: inside a
// closed object all do; in the pocket a terrain or a floor slab closes off where it meets
// the walls, the rays that meet the floor beneath do not. Four points per element, 8 x 8
// where the verdict changes. `stop` ends it early, its shares then partial.
std::vector<double> open_share(const Mesh& mesh, const RayScene& rays, std::stop_token stop = {});

// The same shares, and where each element's open part lies: its open points where it was
// measured on the 8 x 8 grid and only some are open. An element's light leaves from its open part:
// shot from its centroid, a wall element cut by a terrain sent its light from under it, where the
// hemi-cube looks through the terrain's culled back into the pocket, which never shoots again
// (bumprad-bench-scale's terrain came out 2.8 % dark).
struct OpenParts {
  std::vector<double> share;
  // Per element measured on the grid and partly open, its open points (bit 8a + b for the
  // point at ((a + 0.5) / 8, (b + 0.5) / 8)); kWhole for every other element.
  std::vector<std::uint64_t> cells;
  static constexpr std::uint64_t kWhole = ~std::uint64_t(0);
  bool partly_open(std::uint32_t element) const {
    return cells[element] != kWhole && share[element] > 0;
  }
};
OpenParts open_parts(const Mesh& mesh, const RayScene& rays, std::stop_token stop = {});

// The open grid points of an element's `cells` (as OpenParts::cells).
std::vector<Vec3> open_points(const Mesh& mesh, const Element& element, std::uint64_t cells);
// The centre of an element's open part: the mean of its open points where it is partly open,
// else (or with `open` null: all open) its centroid.
Vec3 open_centre(const Mesh& mesh, const OpenParts* open, std::uint32_t element);

Rgb interpolate(const Element& element, std::span<const Rgb> vertex_values, double u, double v);

}  // namespace bumprad
