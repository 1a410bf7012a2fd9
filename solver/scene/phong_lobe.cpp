#include "solver/scene/phong_lobe.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace bumprad {
namespace {

// The share of a cos^n lobe about a direction at elevation beta (radians, negative below)
// that lies above the plane. A cone of half-angle a about the lobe's axis has the fraction
// acos(-tan(beta) / tan(a)) / pi of its circle above (1 for a < beta, 0 for a < -beta); the
// lobe's cos a is u^(1/(n+1)) for uniform u, so the share is the mean of that fraction over
// u. Wholly above when cos^(n+1)(beta) is negligible; otherwise a 64-point midpoint rule over
// the u where the cone crosses the plane (the rest is 1 or 0).
double share_above(double beta, double n) {
  const double crossing = std::pow(std::cos(beta), n + 1);  // u below this: a > |beta|
  const double full = beta > 0 ? 1 - crossing : 0;
  if (crossing < 1e-6) return full;
  constexpr int kSteps = 64;
  const double tan_beta = std::tan(beta);
  double sum = 0;
  for (int k = 0; k < kSteps; ++k) {
    const double cos_a = std::pow(crossing * (k + 0.5) / kSteps, 1 / (n + 1));
    const double tan_a = std::sqrt(std::max(0.0, 1 - cos_a * cos_a)) / cos_a;
    sum += std::acos(std::clamp(-tan_beta / tan_a, -1.0, 1.0)) / kPi;
  }
  return full + crossing * sum / kSteps;
}

}  // namespace

PhongLobe::PhongLobe(const Vec3& mirror, const Vec3& normal, double exponent)
    : frame_(frame_about(mirror)), normal_(normal), exponent_(exponent) {}

double PhongLobe::above() const {
  if (above_ < 0)
    above_ = share_above(std::asin(std::clamp(glm::dot(frame_.z, normal_), -1.0, 1.0)), exponent_);
  return above_;
}

Vec3 PhongLobe::direction(double u1, double u2) const {
  const double cos_a = std::pow(u1, 1 / (exponent_ + 1));
  const double sin_a = std::sqrt(std::max(0.0, 1 - cos_a * cos_a));
  const double phi = 2 * kPi * u2;
  return frame_.to_world(Vec3(sin_a * std::cos(phi), sin_a * std::sin(phi), cos_a));
}

bool PhongLobe::sample(Random& random, Vec3& out) const {
  for (int attempt = 0; attempt < 64; ++attempt) {
    const double u1 = random.next();
    out = direction(u1, random.next());
    if (glm::dot(out, normal_) > 0) return true;
  }
  return false;
}

double PhongLobe::pdf(const Vec3& d) const {
  const double cos_a = glm::dot(d, frame_.z);
  if (cos_a <= 0 || glm::dot(d, normal_) <= 0 || above() <= 0) return 0;
  return (exponent_ + 1) / (2 * kPi) * std::pow(cos_a, exponent_) / above();
}

}  // namespace bumprad
