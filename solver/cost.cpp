#include "solver/cost.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "solver/radiosity/map_basis.h"
#include "solver/radiosity/shot_form_factors.h"
#include "solver/render/error_estimate.h"
#include "solver/scene/camera.h"
#include "solver/scene/mesh.h"

namespace bumprad {
namespace {

// Per shot, measured on the 2-core machine of the README (llvmpipe, Embree): cornell (2,305
// elements, hemi-cube 150) 3.4 ms; the room family of bumprad-bench-scale 9.5 ms at 10k
// elements, 26.5 ms at 100k, 69 ms at 300k and 225 ms at 1M, where most receivers fall
// between hemi-cube pixels and take ray-cast form factors (grouped: one pass over them).
// Since far groups are drawn by proxies (2026-12-07) the room's shots take 5.6, 12-14 and
// 67 ms at 10k, 100k and 1M: 6e-8 s an element beyond 100k. (3e-7 put the 1M room at 0.21
// of its estimate.)
constexpr double kShotFixed_s = 5e-4;
constexpr double kPerHemicubePixel_s = 2e-8;  // per R^2
constexpr double kPerElement_s = 1e-7;        // per element per shot
constexpr double kPerMapValue_s = 1e-7;       // per bumpy vertex and map value, per shot
// A group of a mesh's small triangles (mesh.h) blends the visibility its lookouts' rays
// find, four lookouts of 64 rays each a group, every shot: 7 ms a shot for the room
// family's 266 groups, 16 ms for the objects family's 604. (A shot from a patch smaller
// than the scene's natural one takes 16 rays a lookout, about half the cost: not counted.
// A cluster's shot, nine rays a lookout: not counted either; the objects family, whose
// balls shoot as clusters, ran at 0.47-0.55 of its estimate; 0.58-0.66 since the shots'
// proxies and 1e-7 s an element.)
constexpr double kPerGroup_s = 2.5e-5;
// A non-diffuse shooter's specular transfer (paper-room: 0.55 ms mean for its mirror, 1.6 ms
// for its glossy sphere).
constexpr double kSpecularShot_s = 1.5e-3;
// The near field: per near receiver and point of the shooter (four an element, at most
// kNearFieldPoints), a polygon form factor and, for receivers the hemi-cube missed, a shadow
// ray; two facing 1 m quads 0.1 m apart in 64 x 64-element patches took 20.6 s for two
// shots at 96 x 96 elements (9,216 receivers x 16,384 points each) before the points were
// bounded, 25.1 s at 128 x 128 (16,384 x 16,384).
constexpr double kPerNearPoint_s = 5e-8;
// Shots: each takes the patch with most unshot power and sends on the share its receivers
// reflect, so the unshot power falls about as exp(-(1 - rho) shots / P') for P patches of
// mean reflectance rho, P' a fraction of P (the brightest shoot first). Measured: cornell
// (632 patches, rho 0.56) 750, 894, 1,049 and 1,468 shots to 2 %, 1 %, 0.5 % and 0.1 %
// unshot; wrinkled-box (456, 0.64) 660 to 1 %; the room and terrain families of
// bumprad-bench-scale 263-283 to 1 % at any size. This constant puts them within 0.85-1.15
// of it; paper-room's 1,182 to 5 % is 1.5 times it (its mirror's many small patches,
// which reflect little diffusely, weigh the mean reflectance down). A cluster counts as one
// patch: the objects family's 100 balls (600 patches) took 604 / 622 shots at 10k / 90k
// triangles against 519 / 715 expected.
constexpr double kShotsPerPatch = 0.13;
// Per element, once: the set-up before the first shot (mesh, weld, groups, rays, open
// shares, near sets), and the view pass's part that grows with the mesh (vertex values, the
// near field's shading, rays into a larger scene) at the same pixel count. The room family
// of bumprad-bench-scale (2026-12-07): set-up 1.3-1.5e-5 s an element at 10k triangles,
// 0.8-1.5e-5 at 100k, 7.3e-6 at 1M; its view pass at 256 x 256 0.4, 0.8-1.0 and 4.8 s, 4.4e-6 s
// an element beyond the pixels' part; two quads of a million elements in all took 8.5 s to
// set up. (3e-5 and 2.5e-5, fitted before the set-up's and the near field's costs fell, put
// the 1M room at 0.30 of its estimate.) Since the near field's terms are taken a tree node
// at a time the 1M room's view takes 0.7 s; the view constant now stands for imported models
// beside coarse surfaces (the models family at 955k triangles: 5.2 s, 5.4e-6 s an element).
constexpr double kSetupPerElement_s = 1.5e-5;
constexpr double kViewPerElement_s = 5e-6;
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
  const std::vector<double> sizes = object_element_sizes(scene);
  double emitters = 0, elements = 0;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    const double n = double(estimate_element_count(o, sizes[i]));
    elements += n;
    const Rgb& e = scene.materials[std::size_t(o.material)].emission;
    if (scene.solver.direct_light == DirectLight::Exact && e.r + e.g + e.b > 0) emitters += n;
  }
  const double per_hit_s =
      emitters > 0 ? (1 + c.shadow_rays) * kPerRay_s + emitters * kPerEmitterElement_s : kPerRay_s;
  // Adaptive antialiasing samples about a quarter of the pixels again (16 % of paper-room's).
  const int m = adaptive_antialias(c);
  const double samples = double(c.width) * c.height *
                         (c.antialias * c.antialias + (m > c.antialias ? m * m / 4.0 : 0));
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

namespace {

// What one object brings to the solve.
struct Part {
  double elements = 0, patches = 0, groups = 0, side = 0, element_size = 0;
  Vec3 lo, hi;
  bool emitter = false, specular = false, bumpy = false, near_receiver = true, flat = false;
  // Likely a cluster (solver/radiosity/clusters.h): a small smooth diffuse object of several
  // patches, which shoot as one (its convexity is not checked here).
  bool cluster = false;
  double reflectance = 0;
  // The shooters it brings: its patches, or one cluster.
  double shooters() const { return cluster ? 1 : patches; }
};

std::vector<Part> parts_of(const Scene& scene) {
  const std::vector<double> sizes = object_element_sizes(scene);
  const std::vector<PatchEstimate> patches = estimate_patches(scene);
  std::vector<Part> parts;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    const Material& m = scene.materials[std::size_t(o.material)];
    const PatchEstimate& p = patches[i];
    Part part;
    part.elements = double(estimate_element_count(o, sizes[i]));
    part.patches = double(p.count);
    part.groups = double(p.groups);
    part.side = p.side;
    part.element_size = p.element;
    std::tie(part.lo, part.hi) = object_bounds(o);
    part.emitter = m.emission.r + m.emission.g + m.emission.b > 0;
    part.specular = m.specular > 0;
    part.bumpy = o.bump >= 0;
    part.reflectance = (m.reflectance.r + m.reflectance.g + m.reflectance.b) / 3;
    part.flat = std::holds_alternative<QuadShape>(o.shape);
    // A mesh's triangles of at most one element receive in groups, outside the near field.
    if (const auto* mesh = std::get_if<TriangleMeshShape>(&o.shape))
      part.near_receiver = part.elements > double(mesh->triangles.size());
    part.cluster = p.count >= 2 && !part.specular &&
                   (std::holds_alternative<SphereShape>(o.shape) ||
                    (std::holds_alternative<TriangleMeshShape>(o.shape) &&
                     std::get<TriangleMeshShape>(o.shape).smooth));
    parts.push_back(part);
  }
  Vec3 lo(INFINITY), hi(-INFINITY);
  for (const Part& p : parts) lo = glm::min(lo, p.lo), hi = glm::max(hi, p.hi);
  for (Part& p : parts)
    p.cluster = p.cluster && glm::length(p.hi - p.lo) <= glm::length(hi - lo) / 16;
  return parts;
}

// The gap between two boxes (0 where they overlap).
double gap(const Part& a, const Part& b) {
  const Vec3 d = glm::max(Vec3(0), glm::max(a.lo - b.hi, b.lo - a.hi));
  return glm::length(d);
}

// The near field of one shot from `a`: its receivers (elements of other objects, and of its
// own faces where it has several, within kNearFieldSizes patch sides) times the shooter's
// points.
double near_field_s(const std::vector<Part>& parts, const Part& a) {
  const double radius = kNearFieldSizes * a.side, reach = a.side + 2 * radius;
  double receivers = 0;
  for (const Part& b : parts) {
    if (!b.near_receiver || (&b == &a && a.flat) || gap(a, b) >= radius) continue;
    receivers += std::min(b.elements, reach * reach / (b.element_size * b.element_size));
  }
  const double k = a.side / a.element_size;  // the largest patch's side, in elements
  return receivers * std::min(4 * std::min(a.elements, k * k), double(kNearFieldPoints)) *
         kPerNearPoint_s;
}

double shots_for(const std::vector<Part>& parts, const SolverSettings& s) {
  double patches = 0, emitters = 0, reflected = 0;
  for (const Part& p : parts) {
    patches += p.shooters();
    emitters += p.emitter ? p.shooters() : 0;
    reflected += p.shooters() * p.reflectance;
  }
  if (patches == 0) return 0;
  // A tolerance shoots on, the unshot target falling to a third a round, at most to 1e-4;
  // a target of 0 is never met, and every shot is spent.
  const double target = s.tolerance > 0 ? 1e-4 : s.unshot_fraction;
  if (!(target > 0)) return s.max_shots;
  const double rho = std::min(0.95, reflected / patches);
  const double shots = kShotsPerPatch * patches * std::log(1 / std::min(target, 1.0)) / (1 - rho);
  return std::min(double(s.max_shots), std::max(shots, emitters));
}

}  // namespace

double expected_shots(const Scene& scene) {
  return shots_for(parts_of(scene), scene.solver);
}

CostEstimate estimate_cost(const Scene& scene) {
  const SolverSettings& s = scene.solver;
  // A tolerance may render with more rays a pixel than the camera asks (solution.h): that is
  // counted. Its extra adaptive levels are not: solve() takes them only within the time a
  // job allows (refine_within_s), and a level's cost, a whole solve on up to four times the
  // elements, is what the one before it measured.
  Scene rendered = scene;
  if (s.tolerance > 0)
    rendered.camera.antialias =
        std::max(rendered.camera.antialias, SolverSettings::kToleranceAntialias);
  CostEstimate e = estimate_render_cost(rendered);
  const std::vector<Part> parts = parts_of(scene);
  double elements = 0, bumpy = 0, patches = 0, shooters = 0, emitters = 0, groups = 0;
  for (const Part& p : parts) {
    elements += p.elements;
    groups += p.groups;
    bumpy += p.bumpy ? p.elements : 0;
    patches += p.patches;
    shooters += p.shooters();
    emitters += p.emitter ? p.shooters() : 0;
  }
  const double shots = shots_for(parts, s);
  const double hemicube_s =
      kShotFixed_s + kPerHemicubePixel_s * double(s.hemicube_resolution) * s.hemicube_resolution;
  // The emitters' patches shoot first; the rest of the shots fall to all patches alike. Per
  // shot, a patch's share of them times what its shots cost beyond the hemi-cube.
  const double first = std::min(shots, emitters), rest = shots - first;
  double near_s = 0, specular_s = 0;
  for (const Part& p : parts) {
    const double share = (p.emitter ? first * p.shooters() / emitters : 0) +
                         rest * p.shooters() / std::max(1.0, shooters);
    if (share == 0) continue;
    // A cluster has no near field, and draws a second half hemi-cube.
    near_s += share * (p.cluster ? hemicube_s : near_field_s(parts, p));
    if (p.specular) specular_s += share * kSpecularShot_s;
  }
  const double map_values =
      s.texture == TextureMode::None || bumpy == 0 ? 0 : double(MapBasis(s.map).size());
  // Each adaptive level may split every element in four (up to the element limit) and
  // solves again from the start.
  for (int level = 0; level <= s.adaptive_levels; ++level) {
    const double scale = std::min(double(1 << (2 * level)), Limits::kMaxElements / elements);
    const double n = elements * std::max(1.0, scale), nb = bumpy * std::max(1.0, scale);
    e.setup_s += kSetupPerElement_s * n;
    double shot_s = hemicube_s + kPerElement_s * n + kPerGroup_s * groups;
    if (s.texture == TextureMode::Shoot) shot_s += kPerMapValue_s * nb * map_values;
    e.solve_s += shots * shot_s + near_s + specular_s;
    if (level == s.adaptive_levels && s.texture == TextureMode::Gather)
      e.solve_s += nb * (hemicube_s + kPerElement_s * n);  // a hemi-cube per bumpy vertex
  }
  e.solve_s += e.setup_s;
  // solver.tolerance: the estimator's traced pixels once (error_estimate.h: paths of about ten
  // rays), a round of estimation (a view of at most 1024 x 512 at the camera's rays) each
  // time the unshot target falls to a third, down to 1e-4, and one for the pixels at the
  // tolerance's rays.
  double rounds = 0;
  if (s.tolerance > 0) {
    const double shooting =
        1 + std::ceil(std::log(std::max(1.0, s.unshot_fraction / 1e-4)) / std::log(3.0));
    rounds = shooting + 1;
    auto view_s = [](Scene view) {
      view.camera.width = std::min(view.camera.width, 1024);
      view.camera.height = std::min(view.camera.height, 512);
      return estimate_render_cost(view).render_s;
    };
    const ErrorEstimateSettings traced;
    e.solve_s += double(traced.pixels) * traced.paths * 10 * kPerRay_s + shooting * view_s(scene) +
                 view_s(rendered);
  }
  e.shots = shots;
  e.solve_terms =
      count(elements) + " elements" +
      (groups > 0 ? " (" + count(groups) + " groups)" : std::string()) + ", " + count(patches) +
      " patches, about " + count(shots) + " shots at hemi-cube " + count(s.hemicube_resolution) +
      (s.adaptive_levels > 0 ? ", " + count(s.adaptive_levels) + " adaptive levels"
                             : std::string()) +
      (map_values > 0
           ? ", " + count(bumpy) + " bumpy elements x " + count(map_values) + " map values"
           : std::string()) +
      (near_s > 0.1 * e.solve_s ? ", a near field of about " + count(near_s) + " s"
                                : std::string()) +
      (rounds > 0
           ? ", up to " + count(rounds) + " error estimates (then, as time allows, finer elements)"
           : std::string());
  return e;
}

}  // namespace bumprad
