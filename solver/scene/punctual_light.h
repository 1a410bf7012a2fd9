// What a punctual light (scene.h) gives a point: its irradiance there, exact up to the one
// shadow ray that says whether the light is seen. The solve's first shot, the view pass's
// direct light and the path tracer's next event all use it, so they agree.
#pragma once

#include "solver/scene/ray_scene.h"
#include "solver/scene/scene.h"

namespace bumprad {

// Irradiance (W/m^2) at x on a surface with shading normal `normal` (maybe perturbed, N'):
// I cos / r^2 for a point or spot (times the spot's cone falloff), E cos for a directional
// light; 0 from behind the surface or when the shadow ray from `from` (x lifted off its
// geometric surface) meets something first.
Rgb punctual_irradiance(const PunctualLight& light, const Vec3& x, const Vec3& normal,
                        const Vec3& from, const RayScene& rays);

// The same before the cosine, for a point whose shading normal is not yet known (a bump's
// N' to come): the unit direction toward the light and the irradiance on a surface facing
// it, 0 when the light is behind `facing`'s plane (the geometric surface) or shadowed.
struct PunctualArrival {
  Vec3 toward;
  Rgb irradiance;
};
PunctualArrival punctual_arrival(const PunctualLight& light, const Vec3& x, const Vec3& facing,
                                 const Vec3& from, const RayScene& rays);

// The power a point or spot light sends out (4 pi I; a spot, I over its cone: 2 pi I (1 -
// cos outer)), the energy ledger's emitted; a directional light's is what the scene
// intercepts, so this returns 0 for one.
Rgb punctual_power(const PunctualLight& light);

}  // namespace bumprad
