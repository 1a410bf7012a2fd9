// The geometry of one element, and the tolerances rays and planes are judged by: its corners
// and their weights at a point, the smooth surface there, points spread over it, how far a
// ray leaves a surface, and when elements count as one plane. Every part of the solver takes
// these from here.
#pragma once

#include <array>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include "solver/scene/mesh.h"
#include "solver/scene/scene.h"

namespace bumprad {

// The corners of `e` (3 or 4), written into `storage`: a polygon for Lambert's formula.
std::span<const Vec3> element_corners(const Mesh& mesh, const Element& e,
                                      std::array<Vec3, 4>& storage);

// Area, centroid and normal of `e` from its corners (the triangles (v0,v1,v2) and
// (v0,v2,v3)); false if it is degenerate.
bool compute_element_geometry(const std::vector<Vertex>& vertices, Element& e);

// The run of `count` elements from `first`, with their total area and area-weighted
// centroid and (unit) normal: a patch or a group.
ElementRun element_run(std::span<const Element> elements, std::uint32_t first, std::uint32_t count);
// How far the run's farthest corner lies from its centroid.
double run_radius(const Mesh& mesh, const ElementRun& run);

// The weights of an element's corners at (u, v) as Embree reports a hit: quads
// p0 + u (p1 - p0) + v (p3 - p0) bilinearly, triangles (1 - u - v) p0 + u p1 + v p2.
std::array<double, 4> corner_weights(const Element& element, double u, double v);
// The element's point at (u, v), so weighed.
Vec3 point_at(const Mesh& mesh, const Element& element, double u, double v);

// m^2 points spread over an element, each standing for an equal part of its area: the
// centres of its m x m bilinear sub-quads, or of a triangle's m^2 sub-triangles on the
// grid of its edges' m-ths (those pointing as it does first, row by row, then the others).
std::vector<Vec3> part_points(const Mesh& mesh, const Element& element, int m);
// The same for m = 2.
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

// Whether triangle (a, b, c) has no area to speak of: its cross product under 1e-12 of its
// longest edge squared. Scene meshes refuse such triangles; imported models drop them.
// The corners of the convex hull of points that lie in one plane, whose normal is `normal`
// (Andrew's monotone chain in the plane).
std::vector<Vec3> convex_hull(std::span<const Vec3> points, const Vec3& normal);

bool degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c);

// `m` turned by `degrees` about x, then y, then z (boxes' rotation_deg, models' transforms).
glm::dmat4 rotated_about_axes(const glm::dmat4& m, const Vec3& degrees);

// How far rays leave their surfaces. Embree intersects in single precision: a ray must
// leave by some ulps of the scene's coordinates, or it meets the surface it left (at 1e-7
// of the diagonal the path-traced Cornell box came out 1.3 % too dark). 4e-6 of the largest
// coordinate is about 64 ulps, and 12 micrometres in wrinkled-box, whose rug lies 1 mm
// above its floor.
double ray_epsilon(const Mesh& mesh);

// How far rays between element centroids and points sampled on patches leave both ends:
// 1e-4 of the scene diagonal. A centroid of a quad that is not quite planar lies off the two
// triangles Embree makes of it, by more than ray_epsilon: at 1e-6 of the diagonal a ray
// from a slightly tilted wall of the Cornell box (coordinates near 550) met the wall itself.
double centroid_ray_offset(const Mesh& mesh);

// How far a hemi-cube's eye sits off its surface: 1e-6 of the scene diagonal. The item
// buffer's depth test, in the hemi-cube's own frame, judges what it sees, not Embree, so it
// needs no more than to leave the plane it stands on.
double hemicube_lift(const Mesh& mesh);

// How far two elements may stray from one plane and still count as in it: their unit
// normals by the length of their difference, their corners by distance from the first
// one's plane through its centroid, in scene diagonals (at least 1).
struct Flatness {
  double normal, offset;
};
// Exactly one plane, up to rounding: a mirror whose image must be exact, an emitter outline
// that stands for its elements in Lambert's formula.
inline constexpr Flatness kOnePlane{1e-9, 1e-9};

// Whether the elements (indices into mesh.elements, at least one) lie in one plane within
// `tolerance`.
bool coplanar(const Mesh& mesh, std::span<const std::uint32_t> elements, Flatness tolerance);

// Whether a patch's elements face apart: their area-weighted normals sum to less than 0.99
// of its area (their mean cosine to the mean normal; 0.99 is about 8 degrees between them).
// A sphere's or a hill's patch is curved; a gently rolling floor's is not. A curved patch's
// neighbours see its flanks, and it shoots from its centroid (ProgressiveSolver).
bool curved(const Mesh& mesh, const Patch& patch);

}  // namespace bumprad
