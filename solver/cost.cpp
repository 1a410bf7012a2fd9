#include "solver/cost.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "solver/radiosity/map_basis.h"
#include "solver/scene/camera.h"
#include "solver/scene/mesh.h"

namespace bumprad {
namespace {

// Measured with `bumprad render` on the 2-core machine of the README (llvmpipe, Embree):
// a hemi-cube shot of cornell costs 1.45 ms at R 150 and 7.9 ms at R 600 with 2,305
// elements, 3.1 ms at R 150 with 8,992; at 139k elements, with most of them under a pixel
// and ray cast instead, 266 ms. Per element the large case is taken, so small scenes are
// over-estimated about threefold rather than large ones under-estimated.
constexpr double kShotFixed_s = 1e-4;
constexpr double kPerHemicubePixel_s = 2e-8;  // per R^2
constexpr double kPerElement_s = 1.5e-6;      // per element per shot
constexpr double kPerMapValue_s = 1e-7;       // per bumpy vertex and map value, per shot
// Per element, once: the set-up before the first shot (mesh, weld, groups, rays, open
// shares, near sets), and the view pass's part that grows with the mesh (vertex values, the
// near field's shading, rays into a larger scene) at the same pixel count. The room family
// of bumprad-bench-scale took 2.6e-5 s and 2.2e-5 s an element from 10k to 1M triangles at
// 256 x 256 (README); two quads of a million elements in all took 8.5 s to set up.
constexpr double kSetupPerElement_s = 3e-5;
constexpr double kViewPerElement_s = 2.5e-5;
// The view pass: 512^2 pixels at 2x2 antialiasing take 0.11 s (1e-7 s a camera ray); a
// glossy surface sends glossy_samples more rays, a mirror up to max_depth more.
constexpr double kPerRay_s = 1e-7;
// Exact direct light, per hit: each shadow ray, and Lambert's form factor per emitter
// element (cornell: 20 of them and 4 rays took the render from 0.07 to 0.77 s).
constexpr double kPerEmitterElement_s = 3e-8;

std::string count(double x) {
  char s[32];
  std::snprintf(s, sizeof s, "%.0f", x);
  std::string digits = s, out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

}  // namespace

CostEstimate estimate_render_cost(const Scene& scene) {
  const Camera& c = scene.camera;
  bool glossy = false, mirror = false;
  for (const Material& m : scene.materials) {
    glossy = glossy || (m.specular > 0 && m.shininess > 0);
    mirror = mirror || (m.specular > 0 && m.shininess == 0);
  }
  const double rays_per_sample =
      1 + (glossy ? c.glossy_samples : 0) + (mirror || glossy ? c.max_depth : 0);
  double emitters = 0;
  if (scene.solver.direct_light == DirectLight::Exact) {
    const double size = default_element_size(scene);
    for (const Object& o : scene.objects) {
      const Rgb& e = scene.materials[std::size_t(o.material)].emission;
      if (e.r + e.g + e.b > 0) emitters += double(estimate_element_count(o, size));
    }
  }
  const double per_hit_s =
      emitters > 0 ? (1 + c.shadow_rays) * kPerRay_s + emitters * kPerEmitterElement_s : kPerRay_s;
  // Adaptive antialiasing samples about a quarter of the pixels again (16 % of paper-room's).
  const int m = adaptive_antialias(c);
  const double samples = double(c.width) * c.height *
                         (c.antialias * c.antialias + (m > c.antialias ? m * m / 4.0 : 0));
  double elements = 0;
  for (const Object& o : scene.objects)
    elements += double(estimate_element_count(o, default_element_size(scene)));
  CostEstimate e;
  e.render_mesh_s = elements * kViewPerElement_s;
  e.render_s = samples * rays_per_sample * per_hit_s + e.render_mesh_s;
  e.render_terms =
      count(c.width) + "x" + count(c.height) + " pixels, " + count(c.antialias * c.antialias) +
      " rays a pixel" + (m > c.antialias ? " (" + count(m * m) + " where they disagree)" : "") +
      ", up to " + count(rays_per_sample) + " rays each" +
      (emitters > 0 ? ", exact direct light from " + count(emitters) + " emitter elements with " +
                          count(c.shadow_rays) + " shadow rays"
                    : std::string());
  return e;
}

CostEstimate estimate_cost(const Scene& scene) {
  CostEstimate e = estimate_render_cost(scene);
  const SolverSettings& s = scene.solver;
  const double size = default_element_size(scene);
  double elements = 0, bumpy = 0;
  for (const Object& o : scene.objects) {
    const double n = double(estimate_element_count(o, size));
    elements += n;
    if (o.bump >= 0) bumpy += n;
  }
  const double map_values =
      s.texture == TextureMode::None || bumpy == 0 ? 0 : double(MapBasis(s.map).size());
  const double hemicube_s =
      kShotFixed_s + kPerHemicubePixel_s * double(s.hemicube_resolution) * s.hemicube_resolution;
  // Each adaptive level may split every element in four (up to the element limit) and
  // solves again from the start.
  for (int level = 0; level <= s.adaptive_levels; ++level) {
    const double scale = std::min(double(1 << (2 * level)), Limits::kMaxElements / elements);
    const double n = elements * std::max(1.0, scale), nb = bumpy * std::max(1.0, scale);
    e.setup_s += kSetupPerElement_s * n;
    double shot_s = hemicube_s + kPerElement_s * n;
    if (s.texture == TextureMode::Shoot) shot_s += kPerMapValue_s * nb * map_values;
    e.solve_s += s.max_shots * shot_s;
    if (level == s.adaptive_levels && s.texture == TextureMode::Gather)
      e.solve_s += nb * (hemicube_s + kPerElement_s * n);  // a hemi-cube per bumpy vertex
  }
  e.solve_s += e.setup_s;
  // solver.tolerance: a round of error estimation (1,024 pixels x 1,024 paths of about ten
  // rays, and a view of at most 256 x 128 at 4 x 4 rays) each time the unshot target falls
  // to a third, down to 1e-4.
  double rounds = 0;
  if (s.tolerance > 0) {
    rounds = 1 + std::ceil(std::log(std::max(1.0, s.unshot_fraction / 1e-4)) / std::log(3.0));
    Scene view = scene;
    view.camera.width = std::min(view.camera.width, 256);
    view.camera.height = std::min(view.camera.height, 128);
    view.camera.antialias = 4;
    e.solve_s += rounds * (1024.0 * 1024 * 10 * kPerRay_s + estimate_render_cost(view).render_s);
  }
  e.solve_terms = count(elements) + " elements x " + count(s.max_shots) + " shots at hemi-cube " +
                  count(s.hemicube_resolution) +
                  (s.adaptive_levels > 0 ? ", " + count(s.adaptive_levels) + " adaptive levels"
                                         : std::string()) +
                  (map_values > 0 ? ", " + count(bumpy) + " bumpy elements x " + count(map_values) +
                                        " map values"
                                  : std::string()) +
                  (rounds > 0 ? ", up to " + count(rounds) + " error estimates" : std::string());
  return e;
}

}  // namespace bumprad
