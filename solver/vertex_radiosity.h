// Smooth shading of a radiosity solution: vertex values as the area-weighted mean of the
// adjacent elements (which share vertices only within a smooth surface), interpolated
// bilinearly inside quads and barycentrically inside triangles.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "solver/mesh.h"

namespace bumprad {

std::vector<Rgb> vertex_radiosity(const Mesh& mesh, std::span<const Rgb> element_radiosity);

// The weights of an element's corners at (u, v) as Embree reports a hit: quads
// p0 + u (p1 - p0) + v (p3 - p0) bilinearly, triangles (1 - u - v) p0 + u p1 + v p2.
std::array<double, 4> corner_weights(const Element& element, double u, double v);

Rgb interpolate(const Element& element, std::span<const Rgb> vertex_values, double u, double v);

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
