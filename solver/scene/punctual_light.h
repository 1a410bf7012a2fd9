// What a punctual light (scene.h) gives a point, straight or through a planar mirror: its
// irradiance there, exact up to the one shadow ray that says whether the light is seen. The
// solve's first shot, the view pass's direct light and highlights, and the path tracer's next
// event all use it, so they agree.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "solver/scene/planar_mirror.h"
#include "solver/scene/ray_scene.h"
#include "solver/scene/scene.h"

namespace bumprad {

// A punctual light as the scene's points see it: the light itself, or its virtual image in a
// planar mirror (position reflected, direction turned, intensity times k_s), which lights
// only what sees it through that mirror.
struct PunctualSource {
  PunctualLight light;
  std::size_t index = 0;               // of the scene's light
  std::optional<PlanarMirror> mirror;  // none: the light itself
};

// Each light, followed by its image in every planar mirror whose front it shines on.
std::vector<PunctualSource> punctual_sources(std::span<const PunctualLight> lights,
                                             std::span<const PlanarMirror> mirrors);

// Irradiance (W/m^2) at x on a surface with shading normal `normal` (maybe perturbed, N'):
// I cos / r^2 for a point or spot (times the spot's cone falloff), E cos for a directional
// light; 0 from behind the surface or when the shadow ray from `from` (x lifted off its
// geometric surface) meets something first (for an image: unless it sees the light through
// the mirror).
Rgb punctual_irradiance(const PunctualSource& light, const Vec3& x, const Vec3& normal,
                        const Vec3& from, const RayScene& rays);

// The same before the cosine, for a point whose shading normal is not yet known (a bump's
// N' to come): the unit direction toward the light and the irradiance on a surface facing
// it, 0 when the light is behind `facing`'s plane (the geometric surface) or shadowed.
struct PunctualArrival {
  Vec3 toward;
  Rgb irradiance;
};
PunctualArrival punctual_arrival(const PunctualSource& light, const Vec3& x, const Vec3& facing,
                                 const Vec3& from, const RayScene& rays);

// The power a point or spot light sends out (4 pi I; a spot, I over its cone: 2 pi I (1 -
// cos outer)), the energy ledger's emitted; a directional light's is what the scene
// intercepts, so this returns 0 for one.
Rgb punctual_power(const PunctualLight& light);

}  // namespace bumprad
