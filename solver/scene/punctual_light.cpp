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

// Whether the light `distance` along unit `d` from `from` reaches it (infinity: a directional
// light; anything on the way, however far, shades the point).
bool seen(const PunctualSource& s, const Vec3& from, const Vec3& d, double distance,
          const RayScene& rays) {
  return s.mirror ? s.mirror->shows(from, d, distance, rays) : !rays.occluded({from, d}, distance);
}

}  // namespace

std::vector<PunctualSource> punctual_sources(std::span<const PunctualLight> lights,
                                             std::span<const PlanarMirror> mirrors) {
  std::vector<PunctualSource> sources;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const PunctualLight& l = lights[i];
    sources.push_back({l, i, std::nullopt});
    for (const PlanarMirror& m : mirrors) {
      const bool directional = l.kind == PunctualLight::Kind::Directional;
      if (directional ? !(glm::dot(l.direction, m.normal) < 0) : !m.in_front(l.position)) continue;
      PunctualLight image = l;
      image.position = m.reflect(l.position);
      image.direction = m.turn(l.direction);
      image.intensity = l.intensity * m.specular;
      sources.push_back({image, i, m});
    }
  }
  return sources;
}

PunctualArrival punctual_arrival(const PunctualSource& s, const Vec3& x, const Vec3& facing,
                                 const Vec3& from, const RayScene& rays) {
  const PunctualLight& l = s.light;
  if (l.kind == PunctualLight::Kind::Directional) {
    const Vec3 toward = -l.direction;
    if (!(glm::dot(facing, toward) > 0)) return {toward, Rgb(0)};
    if (!seen(s, from, toward, std::numeric_limits<double>::infinity(), rays))
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
  if (!seen(s, from, to / distance, distance, rays)) return {d, Rgb(0)};
  return {d, l.intensity * (falloff / r2)};
}

Rgb punctual_irradiance(const PunctualSource& l, const Vec3& x, const Vec3& normal,
                        const Vec3& from, const RayScene& rays) {
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
