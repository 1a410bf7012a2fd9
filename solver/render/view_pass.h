// The view pass: primary rays from the pinhole camera through Embree; each hit shows the
// radiosity interpolated from its element's vertices, as radiance B / pi.
#pragma once

#include <span>
#include <stop_token>

#include "solver/radiosity/near_field.h"
#include "solver/radiosity/perturbed_map.h"
#include "solver/render/lights.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/util/image.h"

namespace bumprad {

// Surface detail for the view pass: bump textures (paper section 2.4), per object a bump
// function or none looked up in the perturbed radiosity map, and colour textures from the
// materials.
struct SurfaceDetail {
  const PerturbedMap* map = nullptr;  // no bumps without it
  std::span<const BumpFunction> bumps;
  std::vector<int> object_bump;         // per object: index into bumps, or -1
  std::span<const Material> materials;  // for colour textures; empty: none
  // Exact direct light per hit (needs materials); the radiosity is then the indirect part.
  const Lights* lights = nullptr;
  std::span<const double> open;  // per element, open_share(); empty: all open
  // With exact direct light: the indirect light near creases and contacts put back exactly
  // (near_field.h) from `reflected`, each element's B - E.
  const NearField* near = nullptr;
  std::span<const Rgb> reflected;
};

// `element_radiosity` is per element (e.g. a Snapshot's). Back faces and misses are black.
// A bumpy point shows its vertices' radiosity plus the map's change from N to the perturbed
// N' (so a zero-amplitude bump renders exactly as no bump), interpolated across the
// element. A colour texture scales the reflected part: B = E + (B - E) rho(u,v) / mean.
// Surfaces with a specular fraction k_s add k_s times what they reflect (the second pass):
// mirrors recurse up to camera.max_depth, glossy surfaces average camera.glossy_samples
// lobe rays. Rows are shared among the machine's cores; images do not depend on them.
// `stop` ends the render within a row; the image is then unfinished.
Image render_view(const Mesh& mesh, const RayScene& rays, const Camera& camera,
                  std::span<const Rgb> element_radiosity, const SurfaceDetail& detail = {},
                  std::stop_token stop = {});

}  // namespace bumprad
