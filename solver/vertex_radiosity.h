// Smooth shading of a radiosity solution: vertex values as the area-weighted mean of the
// adjacent elements (which share vertices only within a smooth surface), counting only the
// part of each element open to the scene, interpolated bilinearly inside quads and
// barycentrically inside triangles.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "solver/mesh.h"
#include "solver/ray_scene.h"

namespace bumprad {

// `open` (per element, from open_share; empty: all open) weights each element's area; the
// radiosity is then that of each element's open part.
std::vector<Rgb> vertex_radiosity(const Mesh& mesh, std::span<const Rgb> element_radiosity,
                                  std::span<const double> open = {});

// The share of each element's area open to the scene rather than buried under or inside
// other geometry (a floor under a block, a ceiling behind a lamp mounted on it). Buried
// parts get no light; averaged into a vertex they would darken the open elements beside
// them (at the Cornell box's block bases, 6 % too dark). Four points per element; a point
// is buried when rays along its normal and tilted 60 degrees four ways all meet back faces
// (the inside of a closed object) first.
std::vector<double> open_share(const Mesh& mesh, const RayScene& rays);

// The weights of an element's corners at (u, v) as Embree reports a hit: quads
// p0 + u (p1 - p0) + v (p3 - p0) bilinearly, triangles (1 - u - v) p0 + u p1 + v p2.
std::array<double, 4> corner_weights(const Element& element, double u, double v);

Rgb interpolate(const Element& element, std::span<const Rgb> vertex_values, double u, double v);

// Four points spread over an element, each standing for a quarter of its area: the centres
// of its 2 x 2 bilinear sub-quads, or of a triangle's four midpoint sub-triangles.
std::array<Vec3, 4> quarter_points(const Mesh& mesh, const Element& element);

// The smooth surface at (u, v) of an element, interpolated from its corners as radiosity is:
// the surface's (u,v) parameters, its unit normal and its tangents. The view pass and the
// path tracer shade with it.
struct SurfaceAt {
  std::array<double, 4> weights;
  glm::dvec2 uv;
  Vec3 normal, dpdu, dpdv;
};
SurfaceAt surface_at(const Mesh& mesh, const Element& element, double u, double v);

}  // namespace bumprad
