// Closed-form form factors: the exact references the hemi-cube is tested against, and the
// analytic values a solver can fall back on where the hemi-cube fails (near field).
#pragma once

#include <numbers>
#include <span>

#include <glm/geometric.hpp>

#include "solver/scene/mesh.h"
#include "solver/scene/scene.h"

namespace bumprad {

// Differential area at `point` with unit `normal` to a planar polygon (Lambert's contour
// integral), after clipping the polygon to the half-space the normal faces. Any receiver
// normal is allowed, so this is also the exact perturbed form factor at any tilt.
double point_to_polygon(const Vec3& point, const Vec3& normal, std::span<const Vec3> polygon);

// The area of the part of a polygon of at most 4 corners in the half-space the normal faces.
double area_in_front(const Vec3& point, const Vec3& normal, std::span<const Vec3> polygon);

// Differential area at `point` with unit `normal` to element `e` of `mesh`, one-sided (zero
// from behind it): point_to_polygon near it, and beyond kSmallPatchRadii of its `radius`
// (element_radius()) a small patch's A cos cos / (pi r^2), off by at most 1.5 (radius / r)^2
// (2.3 % where it takes over; most where the element is seen at grazing angles), for a few
// multiplications where Lambert's formula takes an arc cosine per edge. Near-field sums meet
// thousands of fine elements a few of their radii away: a wall's vertex beside the 100k
// room's floor (bumprad-bench-scale) holds 1,650 of its triangles in its near set (the view
// pass 1.8 -> 0.6 s), a shooter's 256 near points reach every floor triangle near it (solve
// 5.7 -> 5.0 s). At 4 radii the furnace's worst element (progressive_test) went 1.48 -> 1.61 %.
constexpr double kSmallPatchRadii = 8;
double point_to_element(const Mesh& mesh, const Element& e, double radius, const Vec3& point,
                        const Vec3& normal);
// The small patch's A cos cos / (pi r^2), one-sided, for a patch of vector area A n whose
// centroid lies `d` from a point of unit `normal`.
inline double small_patch(const Vec3& vector_area, const Vec3& d, const Vec3& normal) {
  const double r2 = glm::dot(d, d), cos_r = glm::dot(normal, d),
               area_cos_s = -glm::dot(vector_area, d);
  return cos_r > 0 && area_cos_s > 0 ? area_cos_s * cos_r / (std::numbers::pi * r2 * r2) : 0;
}

// The largest distance from an element's centroid to its corners.
double element_radius(const Mesh& mesh, const Element& e);

// The polygon's vector form factor at `point` (Arvo 1994's irradiance vector over pi): for
// every unit normal N whose plane leaves the whole polygon in front, point_to_polygon(point,
// N, polygon) = N . polygon_vector(point, polygon), so one vector answers for all such N.
Vec3 polygon_vector(const Vec3& point, std::span<const Vec3> polygon);

// atan2(y, x) for y >= 0 (the angle between two vectors from |a x b| and a . b), within
// 1e-15: Cephes' rational approximation of atan. Lambert's formula takes one per edge, and
// glibc's atan2, which switches the rounding mode on every call, was a fifth of the view
// pass's time.
double angle(double y, double x);

// Area to area: two coaxial parallel a x b rectangles a distance c apart (Howell C-11).
double parallel_rectangles(double a, double b, double c);

// Area to area: from a rectangle of width w to a perpendicular one of height h, sharing an
// edge of length l (Howell C-14).
double perpendicular_rectangles(double l, double w, double h);

}  // namespace bumprad
