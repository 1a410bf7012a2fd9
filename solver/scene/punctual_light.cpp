#include "solver/scene/punctual_light.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace bumprad {
namespace {

double radians(double degrees) {
  return degrees * kPi / 180;
}

// glTF's spot falloff: ((cos - cos outer) / (cos inner - cos outer))^2, clamped to [0, 1].
double cone(const PunctualLight& l, const Vec3& toward) {
  const double c = glm::dot(l.direction, toward);
  const double outer = std::cos(radians(l.outer_cone_deg)),
               inner = std::cos(radians(l.inner_cone_deg));
  const double t = std::clamp((c - outer) / std::max(1e-3, inner - outer), 0.0, 1.0);
  return t * t;
}

}  // namespace

PunctualArrival punctual_arrival(const PunctualLight& l, const Vec3& x, const Vec3& facing,
                                 const Vec3& from, const RayScene& rays) {
  if (l.kind == PunctualLight::Kind::Directional) {
    const Vec3 toward = -l.direction;
    if (!(glm::dot(facing, toward) > 0)) return {toward, Rgb(0)};
    // Anything on the way toward the light, however far, shades the point.
    if (rays.occluded({from, toward}, std::numeric_limits<double>::infinity()))
      return {toward, Rgb(0)};
    return {toward, l.intensity};
  }
  Vec3 d = l.position - x;
  const double r2 = glm::dot(d, d);
  if (!(r2 > 0)) return {facing, Rgb(0)};
  d /= std::sqrt(r2);
  if (!(glm::dot(facing, d) > 0)) return {d, Rgb(0)};
  const double falloff = l.kind == PunctualLight::Kind::Spot ? cone(l, -d) : 1.0;
  if (!(falloff > 0)) return {d, Rgb(0)};
  const Vec3 to = l.position - from;
  const double distance = glm::length(to);
  if (rays.occluded({from, to / distance}, distance)) return {d, Rgb(0)};
  return {d, l.intensity * (falloff / r2)};
}

Rgb punctual_irradiance(const PunctualLight& l, const Vec3& x, const Vec3& normal, const Vec3& from,
                        const RayScene& rays) {
  const PunctualArrival a = punctual_arrival(l, x, normal, from, rays);
  return a.irradiance * std::max(0.0, glm::dot(normal, a.toward));
}

Rgb punctual_power(const PunctualLight& l) {
  switch (l.kind) {
    case PunctualLight::Kind::Point:
      return 4 * kPi * l.intensity;
    case PunctualLight::Kind::Spot:
      return 2 * kPi * (1 - std::cos(radians(l.outer_cone_deg))) * l.intensity;
    case PunctualLight::Kind::Directional:
      break;
  }
  return Rgb(0);
}

}  // namespace bumprad
