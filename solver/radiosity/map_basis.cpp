#include "solver/radiosity/map_basis.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace bumprad {
namespace {

constexpr std::size_t kHarmonics = 18;

// Real orthonormal spherical harmonics of bands 0, 1, 2 and 4 at a unit direction. Band 3
// is left out: the clamped cosine has no odd band above 1, so its A_3 is 0 and 18 numbers
// carry what 25 would.
std::array<double, kHarmonics> harmonics(const Vec3& d) {
  const double x = d.x, y = d.y, z = d.z, x2 = x * x, y2 = y * y, z2 = z * z;
  return {0.28209479177387814,
          -0.4886025119029199 * y,
          0.4886025119029199 * z,
          -0.4886025119029199 * x,
          1.0925484305920792 * x * y,
          -1.0925484305920792 * y * z,
          0.31539156525252005 * (3 * z2 - 1),
          -1.0925484305920792 * x * z,
          0.5462742152960396 * (x2 - y2),
          2.5033429417967046 * x * y * (x2 - y2),
          -1.7701307697799304 * y * z * (3 * x2 - y2),
          0.9461746957575601 * x * y * (7 * z2 - 1),
          -0.6690465435572892 * y * z * (7 * z2 - 3),
          0.10578554691520431 * (35 * z2 * z2 - 30 * z2 + 3),
          -0.6690465435572892 * x * z * (7 * z2 - 3),
          0.47308734787878004 * (x2 - y2) * (7 * z2 - 1),
          -1.7701307697799304 * x * z * (x2 - 3 * y2),
          0.6258357354491761 * (x2 * (x2 - 3 * y2) - y2 * (3 * x2 - y2))};
}

// A_l: the clamped cosine max(0, n.w) = sum over l, m of A_l Y_lm(n) Y_lm(w) (Ramamoorthi &
// Hanrahan 2001, eq. 8), per harmonic above.
constexpr std::array<double, kHarmonics> kClampedCosine = {
    kPi,       2 * kPi / 3, 2 * kPi / 3, 2 * kPi / 3, kPi / 4,   kPi / 4,
    kPi / 4,   kPi / 4,     kPi / 4,     -kPi / 24,   -kPi / 24, -kPi / 24,
    -kPi / 24, -kPi / 24,   -kPi / 24,   -kPi / 24,   -kPi / 24, -kPi / 24};

}  // namespace

MapBasis::MapBasis(const MapSettings& settings) : kind_(settings.basis) {
  if (kind_ == MapBasisKind::SphericalHarmonics) {
    size_ = kHarmonics;
    constant_.assign(size_, 0.0);
    constant_[0] = 1 / harmonics(Vec3(0, 0, 1))[0];
    return;
  }
  azimuths_ = settings.azimuths;
  for (double t : settings.tilts_deg) tilts_.push_back(t * kPi / 180);
  std::sort(tilts_.begin(), tilts_.end());
  directions_.push_back(Vec3(0, 0, 1));
  for (double tilt : tilts_)
    for (int k = 0; k < azimuths_; ++k) {
      const double phi = 2 * kPi * k / azimuths_;
      directions_.push_back(
          Vec3(std::sin(tilt) * std::cos(phi), std::sin(tilt) * std::sin(phi), std::cos(tilt)));
    }
  size_ = directions_.size();
  constant_.assign(size_, 1.0);
}

void MapBasis::project(const Vec3& w, std::span<double> out) const {
  if (kind_ == MapBasisKind::SphericalHarmonics) {
    const auto y = harmonics(w);
    for (std::size_t k = 0; k < kHarmonics; ++k) out[k] = kClampedCosine[k] * y[k];
    return;
  }
  for (std::size_t s = 0; s < size_; ++s) out[s] = std::max(0.0, glm::dot(directions_[s], w));
}

void MapBasis::project_polygon(std::span<const Vec3> polygon, std::span<double> out) const {
  std::fill(out.begin(), out.begin() + std::ptrdiff_t(size_), 0.0);
  std::vector<double> at(size_);
  constexpr double kAngle = 0.05;  // radians a sub-triangle may span, about
  constexpr int kDepth = 12;       // halvings at most: 4^12 sub-triangles where x touches it
  // A triangle split in four until it spans under kAngle, then its exact solid angle (Van
  // Oosterom & Strackee 1983) at its centroid's direction.
  const auto add = [&](const auto& self, const Vec3& a, const Vec3& b, const Vec3& c,
                       int depth) -> void {
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const Vec3 centroid = (a + b + c) / 3.0;
    const double edge = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    if (depth < kDepth && edge > kAngle * std::min({la, lb, lc, glm::length(centroid)})) {
      const Vec3 ab = (a + b) / 2.0, bc = (b + c) / 2.0, ca = (c + a) / 2.0;
      self(self, a, ab, ca, depth + 1);
      self(self, ab, b, bc, depth + 1);
      self(self, ca, bc, c, depth + 1);
      self(self, ab, bc, ca, depth + 1);
      return;
    }
    const double solid = 2 * std::abs(std::atan2(glm::dot(a, glm::cross(b, c)),
                                                 la * lb * lc + glm::dot(a, b) * lc +
                                                     glm::dot(a, c) * lb + glm::dot(b, c) * la));
    if (!(solid > 0) || !(glm::length(centroid) > 0)) return;
    project(glm::normalize(centroid), at);
    for (std::size_t k = 0; k < size_; ++k) out[k] += at[k] * solid / kPi;
  };
  for (std::size_t t = 1; t + 1 < polygon.size(); ++t)
    add(add, polygon[0], polygon[t], polygon[t + 1], 0);
}

MapTerms MapBasis::evaluate(const Vec3& normal) const {
  MapTerms out;
  if (kind_ == MapBasisKind::SphericalHarmonics) {
    const auto y = harmonics(normal);
    out.count = int(kHarmonics);
    for (std::size_t k = 0; k < kHarmonics; ++k) out.index[k] = std::uint32_t(k);
    std::copy(y.begin(), y.end(), out.weight.begin());
    return out;
  }
  auto add = [&](std::uint32_t sample, double weight) {
    out.index[std::size_t(out.count)] = sample;
    out.weight[std::size_t(out.count)] = weight;
    ++out.count;
  };
  if (tilts_.empty()) {
    add(0, 1);
    return out;
  }
  const double theta = std::acos(std::clamp(normal.z / glm::length(normal), -1.0, 1.0));
  double a = std::atan2(normal.y, normal.x) / (2 * kPi) * azimuths_;
  if (a < 0) a += azimuths_;
  const int k0 = std::min(int(a), azimuths_ - 1), k1 = (k0 + 1) % azimuths_;
  const double t = a - k0;
  auto ring = [&](std::size_t r, double w) {
    const std::uint32_t base = std::uint32_t(1 + r * std::size_t(azimuths_));
    add(base + std::uint32_t(k0), w * (1 - t));
    add(base + std::uint32_t(k1), w * t);
  };
  if (theta >= tilts_.back()) {
    ring(tilts_.size() - 1, 1);
    return out;
  }
  const std::size_t r =
      std::size_t(std::upper_bound(tilts_.begin(), tilts_.end(), theta) - tilts_.begin());
  const double lo = r == 0 ? 0 : tilts_[r - 1];
  const double u = (theta - lo) / (tilts_[r] - lo);
  if (r == 0)
    add(0, 1 - u);
  else
    ring(r - 1, 1 - u);
  ring(r, u);
  return out;
}

}  // namespace bumprad
