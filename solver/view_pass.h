// The view pass: primary rays from the pinhole camera through Embree; each hit shows the
// radiosity interpolated from its element's vertices, as radiance B / pi.
#pragma once

#include <span>

#include "solver/image.h"
#include "solver/mesh.h"
#include "solver/ray_scene.h"

namespace bumprad {

// `element_radiosity` is per element (e.g. a Snapshot's). Back faces and misses are black.
// Rows are shared among the machine's cores.
Image render_view(const Mesh& mesh, const RayScene& rays, const Camera& camera,
                  std::span<const Rgb> element_radiosity);

}  // namespace bumprad
