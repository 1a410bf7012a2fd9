// Bump (height) functions F(u,v), Blinn's perturbed normal (Blinn 1978), and normal maps. The
// perturbed radiosity map never depends on them, so a new bump function or normal map only
// changes rendering.
#pragma once

#include <glm/vec2.hpp>

#include "solver/scene/scene.h"

namespace bumprad {

struct BumpSample {
  double height;
  double du, dv;  // dF/du and dF/dv
};

// A height function's value and slopes; a normal map has no heights (all zero).
BumpSample evaluate_bump(const BumpFunction& bump, glm::dvec2 uv);

// Blinn's perturbation of the unit normal n of a surface with tangents dpdu, dpdv:
// N' ~ n + s (F_u (n x P_v) - F_v (n x P_u)) / |P_u x P_v|, s = +-1 the orientation of n
// against P_u x P_v. Exact to first order in F on curved and flat surfaces alike; with
// F_u = F_v = 0 it returns n itself.
Vec3 perturb_normal(const Vec3& n, const Vec3& dpdu, const Vec3& dpdv, double f_u, double f_v);

// The shading normal at uv of a surface with unit normal n and tangents dpdu, dpdv: Blinn's
// perturbation for a height function; for a normal map, its normal in the tangent frame of
// n, dpdu (orthogonalised) and the direction of decreasing v (the image's "up"; the frame
// MikkTSpace builds from the same texture coordinates on a flat surface).
Vec3 bumped_normal(const BumpFunction& bump, glm::dvec2 uv, const Vec3& n, const Vec3& dpdu,
                   const Vec3& dpdv);

}  // namespace bumprad
