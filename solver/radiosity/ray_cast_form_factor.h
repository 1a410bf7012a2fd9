// Ray-cast form factors after Wallace, Elmquist & Haines (SIGGRAPH 1989): a receiving point
// against a source area sampled at n points, each standing for its piece dA_k, with
// visibility by shadow rays. The alternative to the hemi-cube (paper section 2.4), and its
// fallback where the hemi-cube aliases.
#pragma once

#include <numbers>
#include <span>

#include "solver/scene/ray_scene.h"
#include "solver/util/math.h"

namespace bumprad {

// A point on a source, the area it stands for and the way that area faces (the side it
// emits from; on a curved source, its own).
struct AreaSample {
  Vec3 point;
  double area;
  Vec3 normal;
};

// One sample's term of the sum below, cos(theta_r) cos(theta_k) dA_k / (pi r_k^2 + dA_k)
// (Wallace eq. 9), the cosines already known to be positive.
inline double wallace_term(double cos_r, double cos_s, double area, double r2) {
  return cos_r * cos_s * area / (std::numbers::pi * r2 + area);
}

// F(dA_r -> A_s) = sum_k V_k cos(theta_r) cos(theta_k) dA_k / (pi r_k^2 + dA_k) (Wallace
// eq. 9): the dA_k term keeps a sample's contribution finite as r -> 0, where the point-to-
// point kernel would blow up. With `rays`, each sample is tested for visibility from the
// receiver; `offset` lifts the rays' ends off both surfaces so that neither hides the other.
double ray_cast_form_factor(const Vec3& receiver, const Vec3& receiver_normal,
                            std::span<const AreaSample> source, const RayScene* rays,
                            double offset);

}  // namespace bumprad
