#include "solver/radiosity/progressive.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <numbers>

#include <glm/geometric.hpp>

#include "common/stopwatch.h"
#include "solver/radiosity/form_factor_exact.h"
#include "solver/radiosity/vertex_radiosity.h"
#include "solver/render/lights.h"
#include "solver/scene/geometry.h"
#include "solver/scene/phong_lobe.h"
#include "solver/scene/texture.h"
#include "solver/util/parallel.h"

namespace bumprad {
namespace {

double channel_sum(const Rgb& c) {
  return c.r + c.g + c.b;
}

// Receivers closer than this many shooter sizes (sqrt of the patch area) are near field.
constexpr double kNearField = 3.0;
double near_field_radius(const Patch& patch) {
  return kNearField * std::sqrt(patch.area);
}

// Shadow rays start and end this far (in scene diagonals) off their surfaces: Embree works
// in single precision, and at 1e-6 a ray from a slightly tilted wall of the Cornell box
// (coordinates near 550) hit the wall itself.
constexpr double kRayOffset = 1e-4;

// Shadow-ray form factors sample a patch at this many points at most.
constexpr std::size_t kRaySamples = 16;

}  // namespace

// The points a shadow-ray form factor samples on a patch, at most kRaySamples: the
// quarter points of a patch of up to four elements, else its elements' centroids, several
// neighbours sharing one element's point beyond kRaySamples elements. Bounded because rays
// are the fallback's whole cost: a patch of 4 x 4 elements cast 64 rays per aliasing
// receiver, 3.3 ms of a 6.4 ms shot on the 8,992-element Cornell box.
std::vector<ProgressiveSolver::RaySample> ProgressiveSolver::ray_samples(const Mesh& mesh,
                                                                         const Patch& patch) {
  std::vector<RaySample> out;
  if (4 * patch.count <= kRaySamples) {
    for (std::uint32_t e = 0; e < patch.count; ++e)
      for (const Vec3& point : quarter_points(mesh, mesh.elements[patch.first + e]))
        out.push_back({point, e, e + 1, 0.25});
    return out;
  }
  const std::size_t groups = std::min<std::size_t>(patch.count, kRaySamples);
  for (std::size_t g = 0; g < groups; ++g) {
    const std::uint32_t begin = std::uint32_t(g * patch.count / groups);
    const std::uint32_t end = std::uint32_t((g + 1) * patch.count / groups);
    out.push_back({mesh.elements[patch.first + (begin + end) / 2].centroid, begin, end, 1});
  }
  return out;
}

// Adds to the entry of q's source in a by-source list (specular queues).
void ProgressiveSolver::add_by_source(std::vector<Queued>& list, const Queued& q) {
  auto it =
      std::find_if(list.begin(), list.end(), [&](const Queued& x) { return x.source == q.source; });
  if (it == list.end()) {
    list.push_back(q);
  } else {
    it->power += q.power;
    it->emission += q.emission;
  }
}

ProgressiveSolver::ProgressiveSolver(const Mesh& mesh, const std::vector<Material>& materials,
                                     const SolverSettings& settings, const RayScene* rays,
                                     std::span<const double> open)
    : mesh_(mesh),
      settings_(settings),
      rays_(rays),
      hemicube_(mesh, settings.hemicube_resolution),
      visible_slot_(mesh.elements.size(), -1),
      open_(open.begin(), open.end()),
      specular_(mesh.elements.size()),
      shininess_(mesh.elements.size()),
      queue_(mesh.elements.size()),
      source_slot_(mesh.patches.size(), -1),
      incident_(mesh.elements.size(), Rgb(0)),
      incident_emission_(mesh.elements.size(), Rgb(0)),
      radiosity_(mesh.elements.size()),
      unshot_(mesh.elements.size()),
      unshot_emission_(mesh.elements.size()),
      direct_(mesh.elements.size(), Rgb(0)),
      patch_unshot_power_(mesh.patches.size(), 0.0),
      rng_(settings.seed) {
  samples_.resize(mesh.patches.size());
  for (std::size_t p = 0; p < mesh.patches.size(); ++p) {
    const Patch& patch = mesh.patches[p];
    for (std::uint32_t e = patch.first; e < patch.first + patch.count; ++e)
      for (const Vec3& point : quarter_points(mesh, mesh.elements[e]))
        samples_[p].push_back({point, mesh.elements[e].area / 4});
    ray_samples_.push_back(ray_samples(mesh, patch));
  }
  if (settings.form_factors == FormFactorMethod::RayCast && !rays)
    throw std::invalid_argument("ray-cast form factors need the mesh's RayScene");
  std::vector<std::uint32_t> elements;
  for (const Patch& patch : mesh.patches) {
    elements.resize(patch.count);
    for (std::uint32_t k = 0; k < patch.count; ++k) elements[k] = patch.first + k;
    planar_patch_.push_back(coplanar(mesh, elements, kNearlyFlat));
  }
  planar_mirror_ = planar_mirrors(mesh, materials);
  reflectance_ = element_reflectance(mesh, materials);
  if (open_.empty()) open_.assign(mesh.elements.size(), 1.0);
  if (open_.size() != mesh.elements.size())
    throw std::invalid_argument("open shares must be given for every element");
  Rgb weighted_rho(0);
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    const Material& m = materials[std::size_t(e.material)];
    specular_[i] = m.specular;
    shininess_[i] = m.shininess;
    radiosity_[i] = unshot_[i] = unshot_emission_[i] = m.emission;
    emitted_ += m.emission * e.area;
    patch_unshot_power_[e.patch] += channel_sum(m.emission) * e.area;
    weighted_rho += m.reflectance * e.area * open_[i];
    total_area_ += e.area * open_[i];
  }
  if (total_area_ > 0) mean_reflectance_ = weighted_rho / total_area_;
}

double ProgressiveSolver::unshot_fraction() const {
  double emitted = channel_sum(emitted_);
  if (emitted <= 0) return 0;
  // Light shot ahead is as far from converged as light not yet shot.
  double unshot = 0;
  for (double p : patch_unshot_power_) unshot += std::abs(p);
  return unshot / emitted;
}

void ProgressiveSolver::attach_map(PerturbedMap* map) {
  map_ = map;
  hemicube_.watch(map ? map->perturbed_elements() : std::vector<bool>{});
}

bool ProgressiveSolver::done() const {
  return shots_ >= settings_.max_shots || unshot_fraction() <= settings_.unshot_fraction;
}

bool ProgressiveSolver::shoot() {
  auto t0 = Clock::now();
  // The largest residual in magnitude shoots: after overshooting (below) a patch's unshot
  // power can be negative, light it has sent ahead of receiving it (Southwell relaxation,
  // Gortler, Cohen & Slusallek 1993).
  auto best = std::max_element(patch_unshot_power_.begin(), patch_unshot_power_.end(),
                               [](double a, double b) { return std::abs(a) < std::abs(b); });
  if (best == patch_unshot_power_.end() || *best == 0) return false;
  const std::uint32_t pi = std::uint32_t(best - patch_unshot_power_.begin());
  const Patch& patch = mesh_.patches[pi];
  // Overshooting (Feda & Purgathofer 1992): a patch with light to shoot also shoots what
  // it is yet to receive, rho times the ambient estimate, and keeps that as a negative
  // residual; most of it does arrive later, so the patch need not shoot again for it.
  // Cornell box to 1 % unshot: 1,746 shots -> 892, the same image error at equal time or
  // better.
  const Rgb ahead = *best > 0 ? ambient() : Rgb(0);

  // The patch shoots the area-weighted mean of its elements' unshot radiosity.
  // Its specular queues shoot too, merged by source.
  Rgb shot_power(0), emission_power(0);
  std::vector<Queued> sources;
  double left = 0;
  shot_weight_.clear();
  for (std::uint32_t e = patch.first; e < patch.first + patch.count; ++e) {
    // An element's share is its reflectance times the ambient light on its open part.
    const Rgb ahead_e = reflectance_[e] * ahead * open_[e];
    shot_weight_.push_back(std::abs(channel_sum(unshot_[e] + ahead_e)) * open_[e] *
                           mesh_.elements[e].area);
    shot_power += (unshot_[e] + ahead_e) * mesh_.elements[e].area;
    emission_power += unshot_emission_[e] * mesh_.elements[e].area;
    unshot_[e] = -ahead_e;
    unshot_emission_[e] = Rgb(0);
    left -= channel_sum(ahead_e) * mesh_.elements[e].area;
    for (const Queued& q : queue_[e]) add_by_source(sources, q);
    queue_[e].clear();
  }
  patch_unshot_power_[pi] = left;
  weigh_ray_samples(pi);

  double angle = 0;
  if (settings_.rotate_hemicube) angle = rng_.next() * (2 * std::numbers::pi);
  Vec3 origin = shot_origin(pi) + patch.normal * (mesh_.diagonal() * 1e-6);
  const Frame frame = frame_about(patch.normal, angle);
  // Ray-cast shots still render the hemi-cube when its pixels are needed: for specular
  // transfer or to shoot the perturbed map.
  const bool ray_cast = settings_.form_factors == FormFactorMethod::RayCast;
  std::future<std::vector<VisibleElement>> aliased;
  if (!ray_cast && rays_ && settings_.alias_pixels > 0)
    aliased = std::async(std::launch::async, [this, pi] { return aliased_form_factors(pi); });
  if (!ray_cast || map_ || !sources.empty()) hemicube_.render(origin, frame, pi);
  find_form_factors(pi, origin, aliased.valid() ? &aliased : nullptr);

  // Element i receives power dB_j A_j F_ji (then dB_i += rho_i dB_j F_ji A_j / A_i).
  double seen = 0;
  for (const VisibleElement& v : visible_) {
    receive(v.element, shot_power * v.form_factor, pi, emission_power * v.form_factor);
    direct_[v.element] +=
        reflectance_[v.element] * emission_power * (v.form_factor / mesh_.elements[v.element].area);
    seen += v.form_factor;
  }
  escaped_ += shot_power * std::max(0.0, 1.0 - seen);
  const double reflected = channel_sum(shot_power - emission_power);
  reflected_shot_ += reflected;
  reflected_escaped_ += reflected * std::max(0.0, 1.0 - seen);
  double specular_s = 0;
  if (!sources.empty()) {
    auto t2 = Clock::now();
    shoot_specular(pi, origin, frame, sources);
    specular_s = seconds_since(t2);
  }
  ++shots_;

  double texture_s = 0;
  if (map_) {
    auto t1 = Clock::now();
    // With exact direct light the map holds the indirect light only.
    const bool exact = settings_.direct_light == DirectLight::Exact;
    map_->shoot(hemicube_, frame, origin, exact ? shot_power - emission_power : shot_power,
                visible_);
    texture_s = seconds_since(t1);
  }
  last_shot_ = {hemicube_.last_render_seconds(), hemicube_.last_accumulate_seconds(), texture_s,
                specular_s, seconds_since(t0)};
  total_.render_s += last_shot_.render_s;
  total_.accumulate_s += last_shot_.accumulate_s;
  total_.texture_s += last_shot_.texture_s;
  total_.specular_s += last_shot_.specular_s;
  total_.total_s += last_shot_.total_s;
  return true;
}

// A patch shoots from the centre of the power it shoots, not of its area: where a block
// stands on a floor, a floor patch's centre can lie under the block, and a hemi-cube there
// sees through the block's walls (their backs face it and are culled) into the room. The
// power's centre lies on the lit part; where even it falls on a dark element (an L-shaped
// lit part), the nearest element that shoots lends its centroid. Curved patches keep their
// centroid.
Vec3 ProgressiveSolver::shot_origin(std::uint32_t pi) const {
  const Patch& patch = mesh_.patches[pi];
  if (!planar_patch_[pi]) return patch.centroid;
  const std::vector<double>& weight = shot_weight_;
  double total = 0;
  Vec3 centre(0);
  for (std::uint32_t k = 0; k < patch.count; ++k) {
    total += weight[k];
    centre += weight[k] * mesh_.elements[patch.first + k].centroid;
  }
  if (!(total > 0)) return patch.centroid;
  centre /= total;
  auto nearest = [&](bool shooting) {
    std::uint32_t best = 0;
    double best_d2 = INFINITY;
    for (std::uint32_t k = 0; k < patch.count; ++k) {
      const Vec3 d = mesh_.elements[patch.first + k].centroid - centre;
      if ((!shooting || weight[k] > 0) && glm::dot(d, d) < best_d2)
        best = k, best_d2 = glm::dot(d, d);
    }
    return best;
  };
  const std::uint32_t under = nearest(false);
  return weight[under] > 0 ? centre : mesh_.elements[patch.first + nearest(true)].centroid;
}

void ProgressiveSolver::receive(std::uint32_t i, const Rgb& incident, std::uint32_t source,
                                const Rgb& emission) {
  const Element& e = mesh_.elements[i];
  Rgb diffuse = reflectance_[i] * incident;
  Rgb specular = specular_[i] * incident;
  radiosity_[i] += diffuse / e.area;
  unshot_[i] += diffuse / e.area;
  if (specular_[i] > 0)
    add_by_source(queue_[i],
                  {source, specular, planar_mirror_[e.surface] ? specular_[i] * emission : Rgb(0)});
  patch_unshot_power_[e.patch] += channel_sum(diffuse + specular);
  absorbed_ += incident - diffuse - specular;
}

void ProgressiveSolver::shoot_specular(std::uint32_t pi, const Vec3& origin, const Frame& frame,
                                       const std::vector<Queued>& sources) {
  const DeltaFormFactors& d = hemicube_.deltas();
  auto ids = hemicube_.item_buffer();
  // Each source's pixels on this hemi-cube: where its light came in from (P in eq. 5).
  std::vector<std::vector<std::uint32_t>> pixels(sources.size());
  for (std::size_t k = 0; k < sources.size(); ++k)
    source_slot_[sources[k].source] = std::int32_t(k);
  for (std::size_t p = 0; p < ids.size(); ++p)
    if (ids[p])
      if (std::int32_t k = source_slot_[mesh_.elements[ids[p] - 1].patch]; k >= 0)
        pixels[std::size_t(k)].push_back(std::uint32_t(p));
  for (const Queued& s : sources) source_slot_[s.source] = -1;

  std::vector<std::uint32_t> touched;
  // With exact direct light the map gets no part of an emitter's image: the view pass
  // computes that light itself.
  const bool exact = settings_.direct_light == DirectLight::Exact;
  auto deposit = [&](std::size_t q, const Rgb& power, const Rgb& emission) {
    if (q >= ids.size() || !ids[q]) {
      escaped_ += power;
      return;
    }
    std::uint32_t i = ids[q] - 1;
    if (incident_[i] == Rgb(0)) touched.push_back(i);
    incident_[i] += power;
    incident_emission_[i] += emission;
    if (map_)
      map_->receive_ray(i, -glm::normalize(frame.to_world(Vec3(d.direction(q)))),
                        exact ? power - emission : power);
  };
  // The Phong lobe about the mirror direction, importance-sampled (pdf ~ cos^n) on 32
  // strata (8 rings of 4) turned per pixel; samples below the surface are dropped and the
  // rest renormalised, so exactly the queued power leaves (the lobe conserves energy). A
  // source seen in many pixels gives each pixel only its share of the 32 strata, the
  // neighbours taking the others: a large source costs one sample a pixel, not 32 (the
  // sphere of paper-room spent 24 ms a shot here).
  const Patch& shooter = mesh_.patches[pi];
  const double n = shininess_[shooter.first];
  // A curved glossy patch (a sphere's) reflects about its elements' normals in turn, not
  // about its centre's alone: the light it throws spreads as the surface turns.
  std::vector<Vec3> normals;
  for (std::uint32_t e = shooter.first; e < shooter.first + shooter.count; ++e)
    normals.push_back(frame.to_local(mesh_.elements[e].normal));
  constexpr int kLobe = 32;
  auto reflect = [&](std::uint32_t p, const Rgb& power, const Rgb& emission, int count, int first) {
    if (n <= 0) return deposit(d.mirror(p), power, emission);
    const Vec3 in(d.direction(p));
    std::array<std::size_t, kLobe> out;
    int valid = 0;
    for (int j = 0; j < count; ++j) {
      const int k = ((first + j) * 13) % kLobe;  // 13 is prime to 32: each stratum once
      const PhongLobe lobe(glm::reflect(-in, normals[std::size_t(first + j) % normals.size()]),
                           Vec3(0, 0, 1), n);
      // Each ring turned, the whole pattern turned per pixel (golden angle).
      const double turn = ((k / 4) * 0.7 + 2.399963 * p) / (2 * std::numbers::pi);
      std::size_t q =
          d.pixel_for(lobe.direction((k / 4 + 0.5) / (kLobe / 4), (k % 4 + 0.5) / 4 + turn));
      if (q < d.size()) out[std::size_t(valid++)] = q;
    }
    if (valid == 0) return deposit(d.mirror(p), power, emission);
    for (int k = 0; k < valid; ++k)
      deposit(out[std::size_t(k)], power / double(valid), emission / double(valid));
  };

  for (std::size_t k = 0; k < sources.size(); ++k) {
    const Queued& s = sources[k];
    double f = 0;
    for (std::uint32_t p : pixels[k]) f += d.dF(p);
    if (f > 0) {
      const int count = std::max(1, kLobe / int(std::min<std::size_t>(pixels[k].size(), kLobe)));
      for (std::size_t j = 0; j < pixels[k].size(); ++j) {  // H_p of eq. 5
        const std::uint32_t p = pixels[k][j];
        reflect(p, s.power * (d.dF(p) / f), s.emission * (d.dF(p) / f), count,
                int(j % kLobe) * count);
      }
      continue;
    }
    // The source is hidden from the patch centre (it lit only part of the patch): its light
    // still arrived along the direction of its centre.
    Vec3 to_source = mesh_.patches[s.source].centroid - origin;
    std::size_t p = d.pixel_for(frame.to_local(glm::normalize(to_source)));
    if (p < d.size())
      reflect(std::uint32_t(p), s.power, s.emission, kLobe, 0);
    else
      escaped_ += s.power;
  }
  // What came from an emitter's image is direct light (a first bounce, seen in a mirror).
  for (std::uint32_t i : touched) {
    receive(i, incident_[i], pi);
    direct_[i] += reflectance_[i] * incident_emission_[i] / mesh_.elements[i].area;
    incident_[i] = incident_emission_[i] = Rgb(0);
  }
}

// Near field (docs/architecture.md; Baum, Rushmeier & Winget 1989): one hemi-cube at the
// patch centre misjudges receivers within a few patch sizes, by +20% for parallel unit
// squares one unit apart. Keep the hemi-cube's visible fraction of the receiver, but take
// its unoccluded form factor as the mean of the exact point-to-polygon values (Lambert)
// over points spread across the shooting patch.
double ProgressiveSolver::near_field_form_factor(std::uint32_t patch, const Vec3& origin,
                                                 std::uint32_t element,
                                                 double hemicube_form_factor) const {
  std::array<Vec3, 4> storage;
  std::span<const Vec3> receiver = element_corners(mesh_, mesh_.elements[element], storage);
  const Vec3& n = mesh_.patches[patch].normal;
  double at_origin = point_to_polygon(origin, n, receiver);
  if (!(at_origin > 0)) return hemicube_form_factor;
  double visible = std::min(1.0, hemicube_form_factor / at_origin);
  // Each point of the shooter counts with the power it shoots (shot_weight_, its element's,
  // which the element's four quarter points share alike): a patch lit at one end sends its
  // near neighbours the light of that end.
  const auto& samples = samples_[patch];
  double mean = 0, weights = 0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const double w = shot_weight_[k / 4];
    mean += w * point_to_polygon(samples[k].point, n, receiver);
    weights += w;
  }
  return weights > 0 ? visible * mean / weights : hemicube_form_factor;
}

// F_pj = F(dA_j -> A_p) A_j / A_p by reciprocity, the receiver at the element's centre.
// Near field, point sampling falls far short
// (tests/solver/radiosity/ray_cast_form_factor_test.cpp): there the rays give only the visible
// share, and Lambert's exact value the rest.
double ProgressiveSolver::ray_cast_form_factor_to(std::uint32_t patch,
                                                  std::uint32_t element) const {
  const Element& e = mesh_.elements[element];
  const Patch& p = mesh_.patches[patch];
  const auto& samples = shot_samples_;
  double f = ray_cast_form_factor(e.centroid, e.normal, samples, p.normal, rays_,
                                  kRayOffset * mesh_.diagonal());
  if (glm::length(e.centroid - p.centroid) < near_field_radius(p)) {
    double open = ray_cast_form_factor(e.centroid, e.normal, samples, p.normal, nullptr, 0);
    double exact = 0;
    std::array<Vec3, 4> storage;
    for (std::uint32_t k = 0; k < p.count; ++k)
      exact += shot_area_[k] / mesh_.elements[p.first + k].area *
               point_to_polygon(e.centroid, e.normal,
                                element_corners(mesh_, mesh_.elements[p.first + k], storage));
    f = open > 0 ? exact * f / open : 0;
  }
  return f * e.area / p.area;
}

// The patch's area as it shoots: each element's part in proportion to its open area
// (open_share), so that rays and Lambert's values from a patch half under a block spread its
// area's worth over the open half, as the hemi-cube from the centre of its power sees it
// (weighed by the whole area, the rays lost the buried half's share: paper-room with 10,972
// elements came out 1.3 % too dark). Not by the power each part shoots: with overshooting
// that mixes signs within a patch, and the furnace's error tripled.
void ProgressiveSolver::weigh_ray_samples(std::uint32_t pi) {
  const Patch& patch = mesh_.patches[pi];
  double open = 0;
  for (std::uint32_t k = 0; k < patch.count; ++k)
    open += mesh_.elements[patch.first + k].area * open_[patch.first + k];
  shot_area_.resize(patch.count);
  for (std::uint32_t k = 0; k < patch.count; ++k) {
    const double area = mesh_.elements[patch.first + k].area;
    shot_area_[k] = open > 0 ? patch.area * area * open_[patch.first + k] / open : area;
  }
  shot_samples_.clear();
  for (const RaySample& r : ray_samples_[pi]) {
    double area = 0;
    for (std::uint32_t k = r.begin; k < r.end; ++k) area += shot_area_[k];
    shot_samples_.push_back({r.point, r.share * area});
  }
}

// Aliasing: a receiver expected to cover fewer than alias_pixels hemi-cube pixels (a top
// face pixel spans (2/R)^2 of the unit hemi-cube) falls between them, seen in a whole pixel
// or not at all, so it takes its form factor from rays instead, near the patch too (where a
// receiver no pixel sees got nothing before: the near field corrects only what the
// hemi-cube saw). Neither the list nor the rays depend on the hemi-cube, so they run while
// it renders.
std::vector<VisibleElement> ProgressiveSolver::aliased_form_factors(std::uint32_t pi) const {
  const Patch& patch = mesh_.patches[pi];
  const double pixel =
      4.0 / (double(settings_.hemicube_resolution) * double(settings_.hemicube_resolution));
  std::vector<VisibleElement> small;
  for (std::uint32_t j = 0; j < mesh_.elements.size(); ++j) {
    const Element& e = mesh_.elements[j];
    Vec3 d = e.centroid - patch.centroid;
    double r2 = glm::dot(d, d);
    if (e.patch == pi) continue;
    double cos_s = glm::dot(patch.normal, d), cos_r = -glm::dot(e.normal, d);
    if (cos_s <= 0 || cos_r <= 0) continue;
    double solid_angle = e.area * cos_r / (r2 * std::sqrt(r2));
    if (solid_angle < settings_.alias_pixels * pixel) small.push_back({j, 0});
  }
  parallel_for(int(small.size()), [&](int k) {
    VisibleElement& s = small[std::size_t(k)];
    s.form_factor = ray_cast_form_factor_to(pi, s.element);
  });
  return small;
}

void ProgressiveSolver::find_form_factors(std::uint32_t pi, const Vec3& origin,
                                          std::future<std::vector<VisibleElement>>* aliased) {
  const Patch& patch = mesh_.patches[pi];
  visible_.clear();
  if (settings_.form_factors == FormFactorMethod::RayCast) {
    if (map_) hemicube_.form_factors();  // lists the bumpy elements' pixels for the map
    std::vector<double> f(mesh_.elements.size(), 0.0);
    parallel_for(int(f.size()), [&](int j) {
      if (mesh_.elements[std::size_t(j)].patch != pi)
        f[std::size_t(j)] = ray_cast_form_factor_to(pi, std::uint32_t(j));
    });
    double total = 0;
    for (std::uint32_t j = 0; j < f.size(); ++j) {
      if (f[j] > 0) visible_.push_back({j, f[j]});
      total += f[j];
    }
    // Sampling errors must not make energy: a patch cannot send out more than it shoots.
    if (total > 1)
      for (VisibleElement& v : visible_) v.form_factor /= total;
    return;
  }

  // Near-field corrections redistribute what the hemi-cube saw among the receivers; its
  // total (one minus the empty pixels) stays as rendered, so no energy is made or lost.
  visible_ = hemicube_.form_factors();
  const double near = near_field_radius(patch);
  std::vector<std::size_t> close;
  double seen = 0;
  for (std::size_t k = 0; k < visible_.size(); ++k) {
    const VisibleElement& v = visible_[k];
    visible_slot_[v.element] = std::int32_t(k);
    seen += v.form_factor;
    if (glm::length(mesh_.elements[v.element].centroid - patch.centroid) < near) close.push_back(k);
  }
  parallel_for(int(close.size()), [&](int k) {
    VisibleElement& v = visible_[close[std::size_t(k)]];
    v.form_factor = near_field_form_factor(pi, origin, v.element, v.form_factor);
  });
  double corrected = 0;
  for (const VisibleElement& v : visible_) corrected += v.form_factor;
  const double scale = corrected > 0 ? seen / corrected : 0;
  for (VisibleElement& v : visible_) v.form_factor *= scale;

  // The aliasing receivers' ray-cast form factors, computed while the hemi-cube rendered.
  if (aliased) {
    const std::vector<VisibleElement> small = aliased->get();
    double total = seen;
    for (const VisibleElement& s : small) {
      if (visible_slot_[s.element] >= 0) {
        double& old = visible_[std::size_t(visible_slot_[s.element])].form_factor;
        total += s.form_factor - old;
        old = s.form_factor;
      } else if (s.form_factor > 0) {
        visible_.push_back(s);
        total += s.form_factor;
      }
    }
    if (total > 1)
      for (VisibleElement& v : visible_) v.form_factor /= total;
  }
  for (const VisibleElement& v : visible_) visible_slot_[v.element] = -1;
}

void ProgressiveSolver::run(const std::function<bool(const Snapshot&)>& on_step,
                            std::stop_token stop) {
  const int every = std::max(1, settings_.preview_every);
  while (!done() && !stop.stop_requested()) {
    if (!shoot()) break;
    if (on_step && shots_ % every == 0 && !done() && !on_step(snapshot())) return;
  }
  if (on_step && !stop.stop_requested()) on_step(snapshot());
}

// Power still to be shot: diffuse (unshot radiosity times area) and queued specular.
Rgb ProgressiveSolver::unshot_power() const {
  Rgb unshot(0);
  for (std::size_t i = 0; i < unshot_.size(); ++i) {
    unshot += unshot_[i] * mesh_.elements[i].area;
    for (const Queued& q : queue_[i]) unshot += q.power;
  }
  return unshot;
}

// The ambient term counts all of it: light a mirror has yet to reflect will arrive too.
// Cohen et al. 1988 spread the unshot power U over the area A and let it bounce in a closed
// room: ambient = U / A / (1 - rho). In an open scene a share e of every bounce leaves
// (measured: the reflected light shot so far that the hemi-cubes saw leave), so
// ambient = (1 - e) U / A / (1 - rho (1 - e)). At 1 % unshot the closed room's term made the
// Cornell box's dimmest face (lit only by light that bounced, facing the open side) 24 %
// too bright and the whole image 0.9 %; this one 18 % and 0.3 % (the rest: the ambient
// light is spread evenly, not where the unshot patches would send it).
Rgb ProgressiveSolver::ambient() const {
  const double stay = reflected_shot_ > 0 ? 1 - reflected_escaped_ / reflected_shot_ : 1;
  return total_area_ > 0 ? stay * unshot_power() / total_area_ / (Rgb(1) - mean_reflectance_ * stay)
                         : Rgb(0);
}

std::vector<Rgb> ProgressiveSolver::display_radiosity() const {
  const Rgb a = ambient();
  std::vector<Rgb> out(radiosity_.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = radiosity_[i] + reflectance_[i] * a;
  return out;
}

Snapshot ProgressiveSolver::snapshot() const {
  return {shots_, unshot_fraction(), done(), display_radiosity(), direct_};
}

EnergyLedger ProgressiveSolver::ledger() const {
  return {emitted_, absorbed_, escaped_, unshot_power()};
}

}  // namespace bumprad
