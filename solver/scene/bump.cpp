#include "solver/scene/bump.h"

#include "solver/scene/texture.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace bumprad {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

double fract(double x) {
  return x - std::floor(x);
}
double smoothstep(double a, double b, double x) {
  double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Perlin's gradient noise on the integer lattice, gradients from a hash of the cell.
double gradient_noise(glm::dvec2 p, std::uint32_t seed) {
  auto hash = [seed](int x, int y) {
    std::uint32_t h =
        std::uint32_t(x) * 0x8da6b343u ^ std::uint32_t(y) * 0xd8163841u ^ seed * 0xcb1ab31fu;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    double a = kTwoPi * (h & 0xffffu) / 65536.0;
    return glm::dvec2(std::cos(a), std::sin(a));
  };
  int x0 = int(std::floor(p.x)), y0 = int(std::floor(p.y));
  glm::dvec2 f = p - glm::dvec2(x0, y0);
  auto fade = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
  double n00 = glm::dot(hash(x0, y0), f), n10 = glm::dot(hash(x0 + 1, y0), f - glm::dvec2(1, 0));
  double n01 = glm::dot(hash(x0, y0 + 1), f - glm::dvec2(0, 1));
  double n11 = glm::dot(hash(x0 + 1, y0 + 1), f - glm::dvec2(1, 1));
  double u = fade(f.x), v = fade(f.y);
  return (1 - v) * ((1 - u) * n00 + u * n10) + v * ((1 - u) * n01 + u * n11);
}

// Wrinkles and cylinders vary along one direction of the (u,v) plane only.
glm::dvec2 across_axis(const BumpFunction& b) {
  double a = b.direction_deg * std::numbers::pi / 180;
  return {std::cos(a), std::sin(a)};
}
double across(const BumpFunction& b, glm::dvec2 p) {
  return glm::dot(p, across_axis(b));
}

// The pattern's height at pattern-space point p (before amplitude).
double pattern(const BumpFunction& b, glm::dvec2 p) {
  switch (b.type) {
    case BumpType::Noise: {
      double h = 0, a = 1;
      for (int o = 0; o < b.octaves; ++o, a *= 0.5, p *= 2.0)
        h += a * gradient_noise(p, b.seed + std::uint32_t(o));
      return h;
    }
    case BumpType::Wrinkles:
      return std::sin(kTwoPi * across(b, p));
    case BumpType::Bricks: {
      // Running bond: bricks twice as long as high, every other row shifted by half.
      double row = std::floor(p.y);
      double x = fract(p.x / 2 + 0.5 * row), y = fract(p.y);
      double m = b.mortar / 2, edge = 0.5 * m;
      double gx = std::min(x * 2, (1 - x) * 2), gy = std::min(y, 1 - y);
      double g = std::min(gx, gy);
      return smoothstep(m - edge, m + edge, g) - 1;  // 0 on a brick, -1 in the groove
    }
    case BumpType::Tiles: {
      double x = fract(p.x), y = fract(p.y);
      double m = b.mortar / 2, edge = 0.5 * m;
      double g = std::min({x, 1 - x, y, 1 - y});
      return smoothstep(m - edge, m + edge, g) - 1;
    }
    case BumpType::Dimples: {
      glm::dvec2 c = glm::dvec2(fract(p.x), fract(p.y)) - 0.5;
      double d2 = glm::dot(c, c) / (b.radius * b.radius);
      return d2 < 1 ? -(1 - d2) * (1 - d2) : 0.0;
    }
    case BumpType::Image: {
      Rgb c = sample_image(*b.image, p, b.wrap);
      return (c.r + c.g + c.b) / 3;
    }
    case BumpType::Cylinder: {
      // Fig. 4f of the paper: each unit strip bulges like half a cylinder.
      double t = 2 * fract(across(b, p)) - 1;
      return std::sqrt(std::max(0.0, 1 - t * t));
    }
    case BumpType::NormalMap:
      break;  // normals, no heights: bumped_normal reads them
  }
  return 0;
}

}  // namespace

BumpSample evaluate_bump(const BumpFunction& b, glm::dvec2 uv) {
  glm::dvec2 p = uv * b.scale + b.offset;
  double h = pattern(b, p);
  double du, dv;
  if (b.type == BumpType::Wrinkles || b.type == BumpType::Cylinder) {
    // Analytic along the varying direction. The cylinder's dh/dt = -t / sqrt(1 - t^2) is
    // limited near the rim, where the slope grows without bound.
    double slope;
    if (b.type == BumpType::Wrinkles) {
      slope = kTwoPi * std::cos(kTwoPi * across(b, p));
    } else {
      double t = 2 * fract(across(b, p)) - 1;
      slope = -2 * t / std::sqrt(std::max(1e-4, 1 - t * t));
    }
    glm::dvec2 axis = across_axis(b);
    du = slope * axis.x * b.scale.x;
    dv = slope * axis.y * b.scale.y;
  } else {
    // Central differences: a thousandth of a pattern cell, or half a texel of a height map.
    double e = 1e-3;
    if (b.type == BumpType::Image) e = 0.5 / std::max(b.image->width, b.image->height);
    du =
        (pattern(b, p + glm::dvec2(e, 0)) - pattern(b, p - glm::dvec2(e, 0))) / (2 * e) * b.scale.x;
    dv =
        (pattern(b, p + glm::dvec2(0, e)) - pattern(b, p - glm::dvec2(0, e))) / (2 * e) * b.scale.y;
  }
  return {b.amplitude * h, b.amplitude * du, b.amplitude * dv};
}

Vec3 perturb_normal(const Vec3& n, const Vec3& dpdu, const Vec3& dpdv, double f_u, double f_v) {
  if (f_u == 0 && f_v == 0) return n;  // bit for bit: a flat bump renders as no bump
  Vec3 cross = glm::cross(dpdu, dpdv);
  double len = glm::length(cross);
  if (!(len > 0)) return n;
  double s = glm::dot(cross, n) < 0 ? -1 : 1;
  Vec3 d = s * (f_u * glm::cross(n, dpdv) - f_v * glm::cross(n, dpdu)) / len;
  return glm::normalize(n + d);
}

Vec3 bumped_normal(const BumpFunction& b, glm::dvec2 uv, const Vec3& n, const Vec3& dpdu,
                   const Vec3& dpdv) {
  if (b.type != BumpType::NormalMap) {
    const BumpSample f = evaluate_bump(b, uv);
    return perturb_normal(n, dpdu, dpdv, f.du, f.dv);
  }
  // glTF's scaled normal: (2 c - 1) with x and y times the strength, in the tangent frame.
  const Rgb c = sample_image(*b.image, uv * b.scale + b.offset, b.wrap);
  const Vec3 local((2 * c.r - 1) * b.strength, (2 * c.g - 1) * b.strength,
                   std::max(0.0, 2 * c.b - 1));
  const Vec3 t = dpdu - n * glm::dot(n, dpdu);
  const Vec3 s = dpdv - n * glm::dot(n, dpdv);
  if (!(glm::length(t) > 0) || !(glm::length(s) > 0)) return n;
  const Vec3 tangent = glm::normalize(t);
  const Vec3 down = glm::normalize(s - tangent * glm::dot(tangent, s));
  const Vec3 m = local.x * tangent - local.y * down + local.z * n;
  return glm::length(m) > 0 ? glm::normalize(m) : n;
}

}  // namespace bumprad
