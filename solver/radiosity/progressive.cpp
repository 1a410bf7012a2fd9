#include "solver/radiosity/progressive.h"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "common/stopwatch.h"
#include "solver/radiosity/perturbed_map.h"
#include "solver/scene/geometry.h"
#include "solver/util/parallel.h"

namespace bumprad {

ProgressiveSolver::ProgressiveSolver(const Mesh& mesh, const std::vector<Material>& materials,
                                     const SolverSettings& settings, const RayScene* rays,
                                     const OpenParts* open, std::stop_token stop)
    : mesh_(mesh),
      settings_(settings),
      residuals_(mesh, materials,
                 open ? std::span<const double>(open->share) : std::span<const double>()),
      form_factors_(make_shot_form_factors(mesh, settings, rays, open, stop)),
      specular_(mesh, materials),
      hemicube_(mesh, settings.hemicube_resolution),
      open_(open),
      rng_(settings.seed) {
  for (const Patch& patch : mesh.patches) curved_patch_.push_back(curved(mesh, patch));
  // Far groups of a model's small triangles are drawn coarse in the shots' item buffers:
  // their own light comes from rays (shot_form_factors.cpp), their pixels only hide what
  // lies behind them. Not a specular group's: specular transfer reads its pixels one by one.
  if (form_factors_->reads_hemicube()) {
    std::vector<bool> diffuse(mesh.groups.size(), true);
    for (const Element& e : mesh.elements)
      if (materials[std::size_t(e.material)].specular > 0) diffuse[e.group] = false;
    hemicube_.use_proxies(group_proxies(mesh, diffuse, stop));
  }
  clusters_ = find_clusters(
      mesh, materials, open ? std::span<const double>(open->share) : std::span<const double>());
  cluster_of_.assign(mesh.patches.size(), -1);
  for (std::size_t c = 0; c < clusters_.size(); ++c)
    for (std::uint32_t p : clusters_[c].patches) cluster_of_[p] = std::int32_t(c);
}

void ProgressiveSolver::shine(std::span<const PunctualSource> lights, const RayScene& rays,
                              std::stop_token stop) {
  if (lights.empty()) return;
  const double epsilon = ray_epsilon(mesh_);
  std::vector<Arrival> arrivals(mesh_.elements.size());
  for (std::uint32_t i = 0; i < arrivals.size(); ++i) arrivals[i] = {i, Rgb(0), Rgb(0)};
  Rgb emitted(0), escaped(0), reflected(0);
  std::vector<Rgb> straight;  // per element, from the last light itself (its images follow it)
  for (const PunctualSource& l : lights) {
    std::vector<Rgb> incident(mesh_.elements.size());
    parallel_for(
        int(mesh_.elements.size()),
        [&](int i) {
          const Element& e = mesh_.elements[std::size_t(i)];
          Rgb irradiance(0);
          for (const Vec3& q : quarter_points(mesh_, e))
            irradiance += punctual_irradiance(l, q, e.normal, q + e.normal * epsilon, rays) / 4.0;
          incident[std::size_t(i)] = irradiance * e.area;
        },
        stop);
    if (stop.stop_requested()) return;
    Rgb received(0);
    for (std::size_t i = 0; i < incident.size(); ++i) {
      arrivals[i].incident += incident[i];
      received += incident[i];
    }
    if (l.mirror) {
      // An image sends on what its mirror reflects of the light (k_s of what the mirror's
      // elements received, which the ledger had counted absorbed there).
      Rgb sent(0);
      for (std::size_t i = 0; i < incident.size(); ++i)
        if (mesh_.elements[i].surface == l.mirror->surface)
          sent += l.mirror->specular * straight[i];
      reflected += glm::max(sent, received);
      escaped += glm::max(Rgb(0), sent - received);
      continue;
    }
    // A directional light sends what the scene intercepts. A point's power that meets no
    // element's front escapes (never below zero: the quarter points are a quadrature).
    const Rgb sent =
        l.light.kind == PunctualLight::Kind::Directional ? received : punctual_power(l.light);
    emitted += glm::max(sent, received);
    escaped += glm::max(Rgb(0), sent - received);
    straight = std::move(incident);
  }
  residuals_.shine(arrivals, emitted, escaped, reflected);
}

void ProgressiveSolver::attach_map(PerturbedMap* map) {
  map_ = map;
  hemicube_.watch(map ? map->perturbed_elements() : std::vector<bool>{});
}

bool ProgressiveSolver::done() const {
  return shots_ >= settings_.max_shots || unshot_fraction() <= settings_.unshot_fraction;
}

bool ProgressiveSolver::shoot(std::stop_token stop) {
  auto t0 = Clock::now();
  const ShotTiming before{hemicube_.render_seconds(), hemicube_.accumulate_seconds()};
  const std::optional<std::uint32_t> next = residuals_.next_patch();
  if (!next) return false;
  if (const Cluster* cluster = cluster_shooting(*next)) return shoot(*cluster, stop);
  const Shooting shooting = residuals_.take(*next);
  const Patch& patch = mesh_.patches[shooting.patch];

  double angle = 0;
  if (settings_.rotate_hemicube) angle = rng_.next() * (2 * std::numbers::pi);
  const Shot shot{shooting.patch, shot_origin(shooting) + patch.normal * hemicube_lift(mesh_),
                  shooting.weight, stop};
  const Frame frame = frame_about(patch.normal, angle);
  form_factors_->begin(shot);
  // Ray-cast shots still render the hemi-cube when its pixels are needed: for specular
  // transfer or to shoot the perturbed map.
  if (form_factors_->reads_hemicube() || map_ || !shooting.sources.empty())
    hemicube_.render(shot.origin, frame, shooting.patch);
  const std::vector<VisibleElement>& visible = form_factors_->find(shot, hemicube_, map_);
  if (stop.stop_requested()) return false;
  residuals_.deliver(shooting, visible);

  double specular_s = 0;
  const bool exact = settings_.direct_light == DirectLight::Exact;
  if (!shooting.sources.empty()) {
    auto t2 = Clock::now();
    const SpecularTransfer::Result reflected = specular_.transfer(
        shooting.patch, shot.origin, frame, hemicube_, shooting.sources, map_, exact, stop);
    residuals_.deliver(shooting.patch, reflected.arrivals, reflected.escaped);
    specular_s = seconds_since(t2);
  }
  ++shots_;

  double texture_s = 0;
  if (map_) {
    auto t1 = Clock::now();
    map_->shoot(hemicube_, frame, shot.origin, mapped_power(shooting), visible, stop);
    texture_s = seconds_since(t1);
  }
  if (stop.stop_requested()) return false;
  time_shot(t0, before, texture_s, specular_s);
  return true;
}

// A cluster shoots as soon as it holds more unshot power than the best patch: its patches
// are small (a ball's sixth), and one at a time they shoot late and seldom (the objects
// family's 100 balls at 90k triangles: 600 patches, 9 % of the light unshot after the
// 1,000-shot cap).
const Cluster* ProgressiveSolver::cluster_shooting(std::uint32_t next) const {
  const Cluster* best =
      cluster_of_[next] >= 0 ? &clusters_[std::size_t(cluster_of_[next])] : nullptr;
  double most = std::abs(residuals_.unshot_power(next));
  for (const Cluster& c : clusters_) {
    double power = 0;
    for (std::uint32_t p : c.patches) power += std::abs(residuals_.unshot_power(p));
    if (power > most) most = power, best = &c;
  }
  return best;
}

// All the cluster's patches take their power and shoot it from its centre, each in its own
// lobes; the perturbed map gets each receiver's light from the centre's direction.
bool ProgressiveSolver::shoot(const Cluster& cluster, std::stop_token stop) {
  auto t0 = Clock::now();
  const ShotTiming before{hemicube_.render_seconds(), hemicube_.accumulate_seconds()};
  std::vector<Shooting> members;
  std::vector<std::vector<Vec3>> lobes;
  for (std::uint32_t p : cluster.patches) {
    members.push_back(residuals_.take(p));
    lobes.push_back(member_lobes(mesh_, mesh_.patches[p], members.back().weight));
  }
  double angle = 0;
  if (settings_.rotate_hemicube) angle = rng_.next() * (2 * std::numbers::pi);
  const Frame frame = frame_about(Vec3(0, 1, 0), angle);
  const std::vector<std::vector<VisibleElement>> visible =
      form_factors_->find(cluster, lobes, frame, hemicube_, stop);
  if (stop.stop_requested()) return false;
  for (std::size_t m = 0; m < members.size(); ++m) residuals_.deliver(members[m], visible[m]);
  ++shots_;
  double texture_s = 0;
  if (map_) {
    auto t1 = Clock::now();
    for (std::size_t m = 0; m < members.size(); ++m)
      map_->shoot(hemicube_, frame, cluster.centre, mapped_power(members[m]), visible[m], stop);
    texture_s = seconds_since(t1);
  }
  if (stop.stop_requested()) return false;
  time_shot(t0, before, texture_s, 0);
  return true;
}

Rgb ProgressiveSolver::mapped_power(const Shooting& shooting) const {
  return settings_.direct_light == DirectLight::Exact ? shooting.power - shooting.emission
                                                      : shooting.power;
}

void ProgressiveSolver::time_shot(Clock::time_point t0, const ShotTiming& before, double texture_s,
                                  double specular_s) {
  last_shot_ = {hemicube_.render_seconds() - before.render_s,
                hemicube_.accumulate_seconds() - before.accumulate_s, texture_s, specular_s,
                seconds_since(t0)};
  total_.render_s += last_shot_.render_s;
  total_.accumulate_s += last_shot_.accumulate_s;
  total_.texture_s += last_shot_.texture_s;
  total_.specular_s += last_shot_.specular_s;
  total_.total_s += last_shot_.total_s;
}

// A patch shoots from the centre of the power it shoots, not of its area: where a block
// stands on a floor, a floor patch's centre can lie under the block, and a hemi-cube there
// sees through the block's walls (their backs face it and are culled) into the room. The
// power's centre lies on the lit part; where even it falls on a dark element (an L-shaped
// lit part), the nearest element that shoots lends its centroid. The centre is moved onto
// the plane of the element nearest it, onto the surface of a gently rolling floor (which
// shot from its centroid until its patches needed to be flat to 0.8 degrees: in
// bumprad-bench-scale's room, a floor patch half under a box sent the room half its light).
// Curved patches (a sphere's) keep their centroid: from their power's centre on the
// surface, a hemi-cube about the patch's normal looks below the surface there, into the
// object and through its culled back faces (the objects family at 100k triangles: 5.5 %
// off the path tracer, 6.5 % so).
Vec3 ProgressiveSolver::shot_origin(const Shooting& shot) const {
  const Patch& patch = mesh_.patches[shot.patch];
  if (curved_patch_[shot.patch]) return patch.centroid;
  const std::vector<double>& weight = shot.weight;
  double total = 0;
  Vec3 centre(0);
  for (std::uint32_t k = 0; k < patch.count; ++k) {
    total += weight[k];
    centre += weight[k] * open_centre(mesh_, open_, patch.first + k);
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
  if (!(weight[under] > 0)) return mesh_.elements[patch.first + nearest(true)].centroid;
  const Element& on = mesh_.elements[patch.first + under];
  return centre - glm::dot(centre - on.centroid, on.normal) * on.normal;
}

void ProgressiveSolver::run(const std::function<bool(const Snapshot&)>& on_step,
                            std::stop_token stop) {
  const int every = std::max(1, settings_.preview_every);
  while (!done() && !stop.stop_requested()) {
    if (!shoot(stop)) break;
    if (on_step && shots_ % every == 0 && !done() && !on_step(snapshot())) return;
  }
  if (on_step && !stop.stop_requested()) on_step(snapshot());
}

Snapshot ProgressiveSolver::snapshot() const {
  return {shots_, unshot_fraction(), done(), display_radiosity(), direct()};
}

}  // namespace bumprad
