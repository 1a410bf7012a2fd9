// The view pass: primary rays from the pinhole camera through Embree; each hit shows the
// radiosity interpolated from its element's vertices, as radiance B / pi. A ViewPass keeps
// what its camera's rays found that no bump function changes, so rendering it again with
// other bump functions (re-texturing, paper section 2.4) costs the shading alone.
#pragma once

#include <memory>
#include <span>
#include <stop_token>

#include "solver/radiosity/near_field.h"
#include "solver/radiosity/perturbed_map.h"
#include "solver/render/lights.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/util/image.h"

namespace bumprad {

// Surface detail for the view pass: bump textures (paper section 2.4) on the objects that
// have a bump function, looked up in the perturbed radiosity map, and colour textures from
// the materials.
struct SurfaceDetail {
  const PerturbedMap* map = nullptr;    // no bumps without it
  std::vector<int> object_bump;         // per object: index into the bump functions, or -1
  std::span<const Material> materials;  // for colour textures; empty: none
  // Exact direct light per hit (needs materials); the radiosity is then the indirect part.
  const Lights* lights = nullptr;
  std::span<const double> open;  // per element, open_share(); empty: all open
  // With exact direct light: the indirect light near creases and contacts put back exactly
  // (near_field.h) from `reflected`, each element's B - E.
  const NearField* near = nullptr;
  std::span<const Rgb> reflected;
};

// The radiosity at the mesh's vertices that the view pass interpolates. An element partly
// buried (open_share() < 1) received its light on its open part alone (a shooter sees only
// that part), spread over its whole area: over the open part its reflected radiosity is
// (B - E) / open. A textured element reflected with its own mean reflectance
// (element_reflectance()): its reflected part is brought to the texture's mean, so that
// vertices interpolate the light arriving, not the checker, and the view pass scales it by
// rho(u,v) / mean per pixel.
std::vector<Rgb> vertex_values(const Mesh& mesh, std::span<const Rgb> radiosity,
                               const SurfaceDetail& detail);

// `element_radiosity` is per element (e.g. a Snapshot's). Back faces and misses are black.
// A bumpy point shows its vertices' radiosity plus the map's change from N to the perturbed
// N' (so a zero-amplitude bump renders as no bump, to single precision), interpolated across the
// element. A colour texture scales the reflected part: B = E + (B - E) rho(u,v) / mean.
// Surfaces with a specular fraction k_s add k_s times what they reflect (the second pass):
// mirrors recurse up to camera.max_depth, glossy surfaces average camera.glossy_samples
// lobe rays. Rows are shared among the machine's cores; images do not depend on them.
//
// A ray whose first hit is a bumpy diffuse surface keeps that hit, the near field's part
// and the direct light's DirectForm; a pixel no bump can change keeps its value; only rays
// whose bounces meet a bump (mirrors and glossy surfaces) are traced again. The first
// render of each row finds all this; an image is the same whether its rows were kept or
// not. Everything the constructor takes must outlive the ViewPass. Thread-safe. With `keep`
// false it is for one image: each row's records are dropped once it is shaded.
class ViewPass {
 public:
  ViewPass(const Mesh& mesh, const RayScene& rays, const Camera& camera,
           std::span<const Rgb> element_radiosity, const SurfaceDetail& detail = {},
           bool keep = true);
  ~ViewPass();
  ViewPass(const ViewPass&) = delete;
  ViewPass& operator=(const ViewPass&) = delete;

  // The image with these bump functions (indexed by SurfaceDetail::object_bump). `stop`
  // ends it within a row; the image is then unfinished (and what was kept stays right).
  Image render(std::span<const BumpFunction> bumps, std::stop_token stop = {}) const;
  // The memory kept so far, in bytes.
  std::size_t bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One image: ViewPass(..., keep = false).render(bumps, stop).
Image render_view(const Mesh& mesh, const RayScene& rays, const Camera& camera,
                  std::span<const Rgb> element_radiosity, const SurfaceDetail& detail = {},
                  std::span<const BumpFunction> bumps = {}, std::stop_token stop = {});

}  // namespace bumprad
