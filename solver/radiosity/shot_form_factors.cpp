#include "solver/radiosity/shot_form_factors.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <unordered_map>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "solver/radiosity/form_factor_exact.h"
#include "solver/radiosity/ray_cast_form_factor.h"
#include "solver/scene/geometry.h"
#include "solver/util/frame.h"
#include "solver/util/math.h"
#include "solver/util/parallel.h"

namespace bumprad {
namespace {

double near_field_radius(const Patch& patch) {
  return kNearFieldSizes * std::sqrt(patch.area);
}

// Shadow-ray form factors sample a patch at this many points at most; a group's lookouts,
// a few a group, afford more.
constexpr std::size_t kRaySamples = 16;
constexpr std::size_t kLookoutSamples = 64;
// A shooter smaller than the scene's natural patch (a square a sixteenth of its diagonal
// across) is nearly a point to the groups it lights: its lookouts take this many. The
// objects family's 600 sphere patches: its solve 10.0 -> 7.3 s at 10k triangles, 22.6 ->
// 18.1 s at 90k, its error the same (2.51 %, 3.21-3.23 %); with every shooter at 16 the
// terrain's hills had gone 1.17 -> 1.35 %.
constexpr std::size_t kSmallShooterLookoutSamples = 16;
// Within the near field, shooters of up to this many elements give Lambert's exact values.
constexpr std::uint32_t kExactElements = 64;
// Normals closer than this (the cosine between them) face alike.
constexpr double kSameFacing = 0.9;
// A hemi-cube whose view of the groups differs from their rays by more than this share of
// the hemisphere does not stand for its patch (HemicubeFormFactors::share_by_rays).
constexpr double kCentreDisagreement = 0.02;

// Sampling errors must not make energy: a patch cannot send out more than it shoots.
void at_most_one(std::vector<VisibleElement>& visible) {
  double total = 0;
  for (const VisibleElement& v : visible) total += v.form_factor;
  if (total > 1)
    for (VisibleElement& v : visible) v.form_factor /= total;
}

// What a shot's receivers outside the groups keep of the `seen` their pixels gave them (of
// it `far` beyond the near field), when the near field changed its receivers' light by
// `near_change` and the groups' rays changed theirs by `groups_change`, the hemi-cube having
// rendered `rendered` in all: the changes come from the rest of the hemisphere, the void and
// the far receivers in the shares the centre sees them (see HemicubeFormFactors::find()).
double kept_light(double rendered, double seen, double far, double near_change,
                  double groups_change) {
  const double void_ = std::max(0.0, 1 - rendered);
  const double to_void = void_ > 0 ? void_ / (void_ + std::max(0.0, far)) : 0;
  return std::max(0.0, seen + near_change * to_void - groups_change * (1 - to_void));
}

// Points spread over a shooting patch, at most `most`, each with the part of `weight` (one
// value per element of the patch: its area or its power) it stands for, as AreaSample::area,
// and facing as its elements do (a curved patch's points face apart): m x m part points
// (geometry.h) of each element, m at most `per_element`, while at least 2 x 2 fit; else the
// elements binned on the patch's plane into a square grid of about `most` cells, one point a cell
// (below) with their weight. Bounded because the points are the cost: unbounded, a patch of 4 x 4
// elements cast 64 rays per aliasing receiver (half of each shot's time on the 8,992-element
// Cornell box), and a 64 x 64-element patch took 16,384 near-field points a receiver. Binned
// in the plane, not taken in the elements' order: a mesh's patch lists its triangles in the
// file's order, so runs of them are strips, and a run's middle triangle, which had stood for
// the whole run, could lie under a box the rest of the run is beside. An element only partly
// open (`open`, or null: all open) stands at its open points, or in a bin at their centre:
// its light leaves from there.
std::vector<AreaSample> spread_points(const Mesh& mesh, const Patch& patch,
                                      std::span<const double> weight, const OpenParts* open,
                                      std::size_t most, int per_element) {
  std::vector<AreaSample> out;
  if (4 * std::size_t(patch.count) <= most) {
    const int m = std::min(per_element, int(std::sqrt(double(most / patch.count))));
    for (std::uint32_t e = 0; e < patch.count; ++e) {
      const Element& element = mesh.elements[patch.first + e];
      std::vector<Vec3> points;
      if (open && open->partly_open(patch.first + e)) {  // about m x m of its open points
        const std::vector<Vec3> all = open_points(mesh, element, open->cells[patch.first + e]);
        const std::size_t step = (all.size() + std::size_t(m * m) - 1) / std::size_t(m * m);
        for (std::size_t k = step / 2; k < all.size(); k += step) points.push_back(all[k]);
      } else {
        points = part_points(mesh, element, m);
      }
      for (const Vec3& point : points)
        out.push_back({point, weight[e] / double(points.size()), element.normal});
    }
    return out;
  }
  const Frame frame = frame_about(patch.normal);
  auto local = [&](std::uint32_t e) {
    const Vec3 d = mesh.elements[patch.first + e].centroid - patch.centroid;
    return glm::dvec2(glm::dot(d, frame.x), glm::dot(d, frame.y));
  };
  glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (std::uint32_t e = 0; e < patch.count; ++e) {
    lo = glm::min(lo, local(e));
    hi = glm::max(hi, local(e));
  }
  const int cells = std::max(1, int(std::sqrt(double(most))));
  const glm::dvec2 cell = glm::max((hi - lo) / double(cells), glm::dvec2(1e-300));
  std::vector<Vec3> sum(std::size_t(cells * cells), Vec3(0));
  std::vector<double> total(sum.size(), 0);
  std::vector<Vec3> normal(sum.size(), Vec3(0));
  auto cell_of = [&](std::uint32_t e) {
    const glm::dvec2 at = (local(e) - lo) / cell;
    const int i = std::clamp(int(at.x), 0, cells - 1), j = std::clamp(int(at.y), 0, cells - 1);
    return std::size_t(j * cells + i);
  };
  for (std::uint32_t e = 0; e < patch.count; ++e) {
    const std::size_t c = cell_of(e);
    sum[c] += weight[e] * open_centre(mesh, open, patch.first + e);
    total[c] += weight[e];
    normal[c] += std::abs(weight[e]) * mesh.elements[patch.first + e].normal;
  }
  // Each cell's point is its weighted centroid moved onto the plane of its element nearest
  // it: on a curved patch the centroid lies off the surface, and rays to it from the surface
  // were hidden by the surface itself (a closed room of hills lost a quarter of its light
  // with ray-cast form factors). The element's own centroid would do for that, but moves a
  // flat patch's point by up to half an element.
  std::vector<std::uint32_t> nearest(sum.size(), 0);
  std::vector<double> best(sum.size(), INFINITY);
  for (std::uint32_t e = 0; e < patch.count; ++e) {
    const std::size_t c = cell_of(e);
    if (!(total[c] > 0) || weight[e] == 0) continue;
    const Vec3 d = mesh.elements[patch.first + e].centroid - sum[c] / total[c];
    if (glm::dot(d, d) < best[c]) best[c] = glm::dot(d, d), nearest[c] = e;
  }
  for (std::size_t c = 0; c < sum.size(); ++c)
    if (total[c] > 0) {
      const Element& on = mesh.elements[patch.first + nearest[c]];
      const Vec3 centre = sum[c] / total[c];
      out.push_back({centre - glm::dot(centre - on.centroid, on.normal) * on.normal, total[c],
                     glm::normalize(normal[c])});
    }
  return out;
}

// Form factors from a shooting patch by shadow rays, for ray casting and for the hemi-cube's
// aliasing fallback.
class PatchRays {
 public:
  PatchRays(const Mesh& mesh, const RayScene& rays, const OpenParts* open)
      : mesh_(mesh), rays_(rays), open_(open) {}
  // Weighs patch `pi`'s samples for its shot, by the power each element shoots or, if
  // `power` is empty, by its open area (see the definition).
  void weigh(std::uint32_t pi, std::span<const double> power);
  // Weighs a cluster instead, for visible_share() alone: see cluster_view().
  void weigh(const Cluster& cluster);
  // F from the weighed patch to `element` (see the definition).
  double form_factor(std::uint32_t patch, std::uint32_t element) const;
  // The same were nothing in the way.
  double unoccluded(std::uint32_t patch, std::uint32_t element) const;
  // The same for the elements of a group far from the patch, as a field quadratic in their
  // positions (see the definition); none if the group is not that far.
  struct Field {
    Vec3 at, value;
    std::array<Vec3, 3> slope, curve, twist;  // d/dx_i; d2/dx_i2; d2/dx dy, dx dz, dy dz
    double scale;                             // 1 / the patch's area
    // The samples' directions from anywhere in the group lie within a cone about `axis`
    // whose half-angle has this sine (-1: no sample faces the group).
    Vec3 axis;
    double cone_sin;
    // F from the patch to an element of the group; none where the element's horizon
    // crosses the cone (some samples in front of it, some behind: the sum's clamped
    // cosines are not the field's).
    std::optional<double> operator()(const Element& e) const {
      const double facing = glm::dot(e.normal, axis);
      if (facing < -cone_sin) return 0.0;  // every sample behind it
      if (facing <= cone_sin) return std::nullopt;
      const Vec3 u = e.centroid - at;
      const Vec3 v =
          value + slope[0] * u.x + slope[1] * u.y + slope[2] * u.z +
          0.5 * (curve[0] * (u.x * u.x) + curve[1] * (u.y * u.y) + curve[2] * (u.z * u.z)) +
          twist[0] * (u.x * u.y) + twist[1] * (u.x * u.z) + twist[2] * (u.y * u.z);
      return scale * e.area * glm::dot(e.normal, v);
    }
  };
  std::optional<Field> unoccluded_field(std::uint32_t patch, const ElementRun& group,
                                        double radius) const;
  // The share of the weighed patch's samples in view from `element` (NaN if none faces it),
  // by its kRaySamples or, for a lookout, its kLookoutSamples (kSmallShooterLookoutSamples
  // from a small shooter).
  enum class Samples { Receiver, Lookout };
  double visible_share(std::uint32_t element, Samples which = Samples::Receiver) const;

 private:
  double shooting_area(std::uint32_t shooter, const Element& receiver,
                       std::span<const Vec3> corners) const;
  // visible_share() of a weighed cluster (see the definition).
  double cluster_view(const Element& e) const;

  const Mesh& mesh_;
  const RayScene& rays_;
  const OpenParts* open_;  // or null: all open
  // The shooting patch's area per element as it shoots, and its ray samples so weighed.
  std::vector<double> shot_area_;
  std::vector<double> shot_radius_;  // per element of the shooter: element_radius()
  std::vector<AreaSample> shot_samples_, lookout_samples_;
  Vec3 cluster_centre_{0};
  double cluster_radius_ = 0;  // 0: a patch is weighed
};

// F_pj = F(dA_j -> A_p) A_j / A_p by reciprocity, the receiver at the element's centre: the
// unoccluded value times the share of the samples the rays see.
double PatchRays::form_factor(std::uint32_t patch, std::uint32_t element) const {
  const double f = unoccluded(patch, element);
  if (!(f > 0)) return 0;
  const double visible = visible_share(element);
  return visible > 0 ? f * visible : 0;
}

// Near field, point sampling falls far short
// (tests/solver/radiosity/ray_cast_form_factor_test.cpp): there Lambert's exact value from
// each of the shooter's elements, while it has at most kExactElements (a receiver then
// costs one polygon each; a finer shooter keeps the samples), or a small patch's beyond
// kSmallPatchRadii of an element that is all open (form_factor_exact.h: the arc cosines
// had been a fifth of the objects family's solve). An element of the shooter takes nothing
// from itself.
double PatchRays::unoccluded(std::uint32_t patch, std::uint32_t element) const {
  const Element& e = mesh_.elements[element];
  const Patch& p = mesh_.patches[patch];
  double f = 0;
  if (p.count <= kExactElements && glm::length(e.centroid - p.centroid) < near_field_radius(p)) {
    std::array<Vec3, 4> storage;
    for (std::uint32_t k = 0; k < p.count; ++k) {
      const std::uint32_t s = p.first + k;
      if (s == element) continue;
      const Element& shooter = mesh_.elements[s];
      const Vec3 d = shooter.centroid - e.centroid;
      const double r2 = glm::dot(d, d), reach = kSmallPatchRadii * shot_radius_[k];
      if (r2 > reach * reach && !(open_ && open_->partly_open(s))) {
        f += small_patch(shot_area_[k] * shooter.normal, d, e.normal);
        continue;
      }
      const std::span<const Vec3> corners = element_corners(mesh_, shooter, storage);
      f += shot_area_[k] / shooting_area(s, e, corners) *
           point_to_polygon(e.centroid, e.normal, corners);
    }
  } else {
    f = ray_cast_form_factor(e.centroid, e.normal, shot_samples_, nullptr, 0);
  }
  return f * e.area / p.area;
}

// The area a partly buried element of the shooter sends its light from, as a receiver's
// Lambert value sees it. That value covers the part in front of the receiver's plane, and
// the buried part is often what lies behind it (the surface that buries it is often the
// receiver's own: a terrain across a wall), so the light it finds left the open part alone:
// the area is the larger of the open part and the part in front, the whole element where the
// receiver sees all of it. Divided by the whole area, the terrain's triangles along the
// walls took a quarter of the light of the walls' cut elements (bumprad-bench-scale's
// terrain 2.3 -> 1.8 % off the path tracer).
double PatchRays::shooting_area(std::uint32_t shooter, const Element& receiver,
                                std::span<const Vec3> corners) const {
  const double area = mesh_.elements[shooter].area;
  const double share = open_ ? open_->share[shooter] : 1;
  if (!(share > 0 && share < 1)) return area;
  return std::max(share * area, area_in_front(receiver.centroid, receiver.normal, corners));
}

// Far from the samples, a group's unoccluded form factors need not be summed over them
// element by element: where every sample lies in front of an element, Wallace's sum is
// n . V(x), V(x) = sum of a_s cos_s w_s / (pi r_s^2 + a_s) over the samples (w_s the unit
// vector to sample s), and V is smooth over the group. Its values at the group's centre and
// ten points a radius about it fit a quadratic field, whose error falls as
// (radius / distance)^3. Against the elements' own sums, over every shot of
// bumprad-bench-scale's 100k-triangle room: 0.09 % RMS beyond 8 radii (0.15 % beyond 6,
// 0.5 % beyond 4; a linear field 0.5 % beyond 8), where a group of about 300 triangles
// took 11 sums instead of 300 (the loop had been a sixth of the solve; 7.25 -> 5.8 s).
// Each element is judged on its own (Field::operator()): on a curved group (an imported
// figure's) most elements see the whole shooter, some see none of it, and only those
// whose horizon crosses it keep their own sums (taken for the whole group, the field
// served 2 % of the models family's grouped elements at 134k triangles). A sample near its
// own horizon (where the sum's clamped cosines bend), too close, or a shooter that takes
// Lambert's exact values there (unoccluded()) leaves the group to its own sums; so do
// groups of kFieldElements or fewer, where the field saves nothing.
constexpr double kFarSizes = 8;
constexpr std::uint32_t kFieldElements = 16;
std::optional<PatchRays::Field> PatchRays::unoccluded_field(std::uint32_t patch,
                                                            const ElementRun& group,
                                                            double radius) const {
  const Patch& p = mesh_.patches[patch];
  if (group.first >= p.first && group.first < p.first + p.count) return std::nullopt;
  if (p.count <= kExactElements &&
      glm::length(group.centroid - p.centroid) < near_field_radius(p) + radius)
    return std::nullopt;  // unoccluded() takes Lambert's exact values there
  // The samples facing the group, each by its direction and how far that turns across it.
  std::vector<std::pair<Vec3, double>> facing;
  Vec3 axis(0);
  for (const AreaSample& s : shot_samples_) {
    const Vec3 d = s.point - group.centroid;
    const double r = glm::length(d);
    if (!(r > kFarSizes * radius)) return std::nullopt;
    const double margin = radius / r, cos_s = -glm::dot(s.normal, d) / r;
    if (std::abs(cos_s) < margin) return std::nullopt;
    if (cos_s > 0) {
      facing.emplace_back(d / r, std::asin(margin));
      axis += d / r;
    }
  }
  double cone = 0;  // the half-angle
  if (!facing.empty()) {
    axis = glm::normalize(axis);
    for (const auto& [w, turn] : facing)
      cone = std::max(cone, std::acos(std::clamp(glm::dot(w, axis), -1.0, 1.0)) + turn);
    if (!(cone < kPi / 2)) return std::nullopt;
  }
  auto sum = [&](const Vec3& x) {
    Vec3 v(0);
    for (const AreaSample& s : shot_samples_) {
      const Vec3 d = s.point - x;
      const double r2 = glm::dot(d, d);
      const Vec3 w = d / std::sqrt(r2);
      const double cos_s = -glm::dot(s.normal, w);
      if (cos_s > 0) v += wallace_term(1, cos_s, s.area, r2) * w;
    }
    return v;
  };
  const Vec3& c = group.centroid;
  const double h = radius;
  Field field{c,
              sum(c),
              {},
              {},
              {},
              1 / p.area,
              facing.empty() ? group.normal : axis,
              facing.empty() ? -1 : std::sin(cone)};
  std::array<Vec3, 3> up, step{Vec3(h, 0, 0), Vec3(0, h, 0), Vec3(0, 0, h)};
  for (int i = 0; i < 3; ++i) {
    up[i] = sum(c + step[i]);
    const Vec3 down = sum(c - step[i]);
    field.slope[i] = (up[i] - down) / (2 * h);
    field.curve[i] = (up[i] - 2.0 * field.value + down) / (h * h);
  }
  const std::array<std::pair<int, int>, 3> pairs{{{0, 1}, {0, 2}, {1, 2}}};
  for (int k = 0; k < 3; ++k) {
    const auto [i, j] = pairs[k];
    field.twist[k] = (sum(c + step[i] + step[j]) - up[i] - up[j] + field.value) / (h * h);
  }
  return field;
}

double PatchRays::visible_share(std::uint32_t element, Samples which) const {
  const Element& e = mesh_.elements[element];
  if (cluster_radius_ > 0) return cluster_view(e);
  const auto& samples = which == Samples::Lookout ? lookout_samples_ : shot_samples_;
  const double open = ray_cast_form_factor(e.centroid, e.normal, samples, nullptr, 0);
  if (!(open > 0)) return std::numeric_limits<double>::quiet_NaN();
  return ray_cast_form_factor(e.centroid, e.normal, samples, &rays_, centroid_ray_offset(mesh_)) /
         open;
}

// The patch's area as it shoots, spread over its elements as their weights are: the power
// each shoots (Shot::weight) or its open area (open_share). Either spreads a patch half
// under a block over its open half, as the hemi-cube from the centre of its power sees it
// (weighed by the whole area, the rays lost the buried half's share: paper-room with 10,972
// elements came out 1.3 % too dark). The power is what a hemi-cube's shot weighs its rays
// by, as it does its near points (near_points()): a floor patch beside a box that floats a
// few centimetres over it is open beneath the box but dark there, and the rays, weighed by
// area, sent the faces of another box 1.3 m away 40 % of the light of the lit strip beside
// the first (bumprad-bench-scale's room). Ray casting weighs by area: with every receiver
// from rays, the power's weights follow overshooting's corrections over the patch (their
// magnitudes; the signs mix), and the furnace's worst element went from 0.3 to 0.9 % off.
void PatchRays::weigh(std::uint32_t pi, std::span<const double> power) {
  cluster_radius_ = 0;
  const Patch& patch = mesh_.patches[pi];
  shot_area_.resize(patch.count);
  shot_radius_.resize(patch.count);
  for (std::uint32_t k = 0; k < patch.count; ++k)
    shot_radius_[k] = element_radius(mesh_, mesh_.elements[patch.first + k]);
  for (std::uint32_t k = 0; k < patch.count; ++k)
    shot_area_[k] = power.empty() ? mesh_.elements[patch.first + k].area *
                                        (open_ ? open_->share[patch.first + k] : 1)
                                  : power[k];
  const double total = std::accumulate(shot_area_.begin(), shot_area_.end(), 0.0);
  for (std::uint32_t k = 0; k < patch.count; ++k)
    shot_area_[k] =
        total > 0 ? patch.area * shot_area_[k] / total : mesh_.elements[patch.first + k].area;
  shot_samples_ = spread_points(mesh_, patch, shot_area_, open_, kRaySamples, int(kRaySamples));
  const double natural = mesh_.diagonal() / 16;
  const std::size_t lookouts =
      patch.area < natural * natural ? kSmallShooterLookoutSamples : kLookoutSamples;
  lookout_samples_ = spread_points(mesh_, patch, shot_area_, open_, lookouts, int(lookouts));
}

void PatchRays::weigh(const Cluster& cluster) {
  cluster_centre_ = cluster.centre;
  cluster_radius_ = cluster.radius;
}

// A cluster's share in view: shadow rays to nine points on the side of its bounding sphere
// that faces the receiver (the point toward it, and eight about that, 0.6 of the radius
// across, or fewer where the receiver is so near that their tangent planes would turn away
// from it). Outside the cluster, so that no ray meets the cluster itself: a point on its own
// surface stands for a patch of it whose mean normal may face the receiver while the point
// itself lies past the cluster's outline from there, and its ray would count as blocked.
double PatchRays::cluster_view(const Element& e) const {
  const Vec3 from = e.centroid + e.normal * centroid_ray_offset(mesh_);
  const Vec3 d = from - cluster_centre_;
  const double distance = glm::length(d), r = cluster_radius_;
  if (!(distance > r) || glm::dot(e.normal, d) >= 0)
    return std::numeric_limits<double>::quiet_NaN();
  const Frame frame = frame_about(d / distance);
  const double lift =
      std::min(1.0, 1.1 * r / distance);  // the points' least height over the centre
  const double ring = std::min(0.6, std::sqrt(1 - lift * lift));
  int seen = 0;
  constexpr int kPoints = 9;
  for (int k = 0; k < kPoints; ++k) {
    const double a = k == 0 ? 0 : ring * std::cos(2 * kPi * k / (kPoints - 1)),
                 b = k == 0 ? 0 : ring * std::sin(2 * kPi * k / (kPoints - 1));
    const Vec3 to = cluster_centre_ + r * frame.to_world(Vec3(a, b, std::sqrt(1 - a * a - b * b)));
    const Vec3 path = to - from;
    const double length = glm::length(path);
    seen += !rays_.occluded({from, path / length}, length);
  }
  return double(seen) / kPoints;
}

// Ray casting: every element's form factor from rays.
class RayCastFormFactors : public ShotFormFactors {
 public:
  RayCastFormFactors(const Mesh& mesh, const RayScene& rays, const OpenParts* open)
      : mesh_(mesh), rays_(mesh, rays, open) {}
  bool reads_hemicube() const override { return false; }
  void begin(const Shot& shot) override { rays_.weigh(shot.patch, {}); }
  std::vector<VisibleElement>& find(const Shot& shot, Hemicube& hemicube, bool map) override;
  std::vector<std::vector<VisibleElement>> find(const Cluster& cluster,
                                                std::span<const std::vector<Vec3>> lobes,
                                                const Frame& frame, Hemicube& hemicube,
                                                std::stop_token stop) override;

 private:
  const Mesh& mesh_;
  PatchRays rays_;
  std::vector<VisibleElement> visible_;
};

std::vector<VisibleElement>& RayCastFormFactors::find(const Shot& shot, Hemicube& hemicube,
                                                      bool map) {
  const std::uint32_t pi = shot.patch;
  visible_.clear();
  if (map) hemicube.form_factors();  // lists the bumpy elements' pixels for the map
  std::vector<double> f(mesh_.elements.size(), 0.0);
  // The shooter's own elements too: a curved patch's that face each other light each other.
  parallel_for(
      int(f.size()), [&](int j) { f[std::size_t(j)] = rays_.form_factor(pi, std::uint32_t(j)); },
      shot.stop);
  for (std::uint32_t j = 0; j < f.size(); ++j)
    if (f[j] > 0) visible_.push_back({j, f[j]});
  at_most_one(visible_);
  return visible_;
}

// Every element outside the cluster: the lobes' value times the share of the cluster's
// facing side its rays see.
std::vector<std::vector<VisibleElement>> RayCastFormFactors::find(
    const Cluster& cluster, std::span<const std::vector<Vec3>> lobes, const Frame&, Hemicube&,
    std::stop_token stop) {
  rays_.weigh(cluster);
  std::vector<double> view(mesh_.elements.size(), 0.0);
  parallel_for(
      int(view.size()),
      [&](int j) {
        if (mesh_.elements[std::size_t(j)].object == cluster.object) return;
        const double share = rays_.visible_share(std::uint32_t(j));
        view[std::size_t(j)] = share > 0 ? share : 0;
      },
      stop);
  std::vector<std::vector<VisibleElement>> out(lobes.size());
  for (std::size_t m = 0; m < lobes.size(); ++m) {
    for (std::uint32_t j = 0; j < view.size(); ++j)
      if (view[j] > 0)
        if (const double f =
                cluster_form_factor(mesh_, lobes[m], cluster.centre, mesh_.elements[j]);
            f > 0)
          out[m].push_back({j, f * view[j]});
    at_most_one(out[m]);
  }
  return out;
}

// The hemi-cube, with the near field put right and the aliasing receivers taken from rays.
class HemicubeFormFactors : public ShotFormFactors {
 public:
  HemicubeFormFactors(const Mesh& mesh, const SolverSettings& settings, const RayScene* rays,
                      const OpenParts* open, std::stop_token stop);
  bool reads_hemicube() const override { return true; }
  void begin(const Shot& shot) override;
  std::vector<VisibleElement>& find(const Shot& shot, Hemicube& hemicube, bool map) override;
  std::vector<std::vector<VisibleElement>> find(const Cluster& cluster,
                                                std::span<const std::vector<Vec3>> lobes,
                                                const Frame& frame, Hemicube& hemicube,
                                                std::stop_token stop) override;

 private:
  // A cluster's receivers from rays, per member (see the definition).
  struct ClusterRays {
    std::vector<std::vector<VisibleElement>> aliased, grouped;
  };
  ClusterRays cluster_rays(const Cluster& cluster, std::span<const std::vector<Vec3>> lobes,
                           std::stop_token stop) const;
  // What needs no hemi-cube, found while it renders (see the definitions).
  struct Prepared {
    std::vector<std::uint32_t> near;  // receivers within near_field_radius
    std::vector<VisibleElement> aliased;
    std::vector<VisibleElement> grouped;
  };
  void near_points(const Shot& shot);
  double near_lambert(std::uint32_t element, bool occluded) const;
  // A near receiver's form factor, and the same with its visible share uncapped.
  struct NearValue {
    double form_factor, uncapped;
  };
  NearValue near_field(const Shot& shot, std::uint32_t element, double hemicube_form_factor) const;
  Prepared prepare(const Shot& shot) const;
  void by_rays(const Shot& shot, Prepared& out) const;
  bool between_pixels(const Element& e, const Vec3& d) const;
  std::vector<VisibleElement> hidden_near(const Shot& shot,
                                          std::span<const std::uint32_t> near) const;
  std::vector<VisibleElement> grouped(const Shot& shot) const;
  // Per lookout, the share of the weighed shooter its rays see (NaN: it faces none of it).
  std::vector<double> lookout_views(std::stop_token stop) const;
  // Element j of groups_[k]: the share of the shooter it sees, its lookouts' `seen` blended.
  double blended_view(std::size_t k, std::uint32_t j, std::span<const double> seen) const;
  void share_by_rays(const Shot& shot);
  double grouped_unoccluded(const Shot& shot, std::uint32_t element) const;
  double beyond_near_points(const Shot& shot, const Vec3& at) const;

  const Mesh& mesh_;
  const RayScene* scene_rays_;
  const int resolution_;
  const double alias_pixels_;
  std::optional<PatchRays> rays_;        // none: no aliasing fallback
  const OpenParts* open_;                // or null: all open
  std::vector<AreaSample> near_points_;  // each with the power it stands for as its area
  // The rectangle around them on the shooter's plane, in its frame about the patch centroid.
  Frame near_frame_;
  glm::dvec2 near_lo_{0}, near_hi_{0};
  bool near_curved_ = false;  // the shooter's elements face apart (curved())
  // A grouped element's visibility, blended from up to four lookouts near it (see the
  // constructor): indices in lookouts_ and their weights.
  struct Blend {
    std::array<std::uint32_t, 4> lookout{};
    std::array<float, 4> weight{};
  };
  void find_lookouts(std::span<const double> open);
  void blend_lookouts(std::stop_token stop);

  std::vector<std::uint32_t> groups_;         // the groups of more than one element
  std::vector<double> group_radius_;          // per group in groups_: run_radius()
  std::vector<std::uint32_t> lookouts_;       // elements whose rays sample the groups' visibility
  std::vector<std::uint32_t> first_lookout_;  // per group in groups_ and one past: in lookouts_
  std::vector<Blend> blends_;                 // per grouped element, groups_' elements in order
  std::vector<std::uint32_t> first_blend_;    // per group in groups_, its first in blends_
  std::vector<bool> grouped_;                 // per element: in one of groups_
  std::future<Prepared> prepared_;
  std::vector<VisibleElement> visible_;
  std::vector<std::int32_t> visible_slot_;  // per element, its entry in visible_ or -1
};

HemicubeFormFactors::HemicubeFormFactors(const Mesh& mesh, const SolverSettings& settings,
                                         const RayScene* rays, const OpenParts* open,
                                         std::stop_token stop)
    : mesh_(mesh),
      scene_rays_(rays),
      resolution_(settings.hemicube_resolution),
      alias_pixels_(settings.alias_pixels),
      open_(open),
      grouped_(mesh.elements.size(), false),
      visible_slot_(mesh.elements.size(), -1) {
  if (!rays || !(settings.alias_pixels > 0)) return;
  rays_.emplace(mesh, *rays, open);
  find_lookouts(open ? std::span<const double>(open->share) : std::span<const double>());
  blend_lookouts(stop);
}

// A group's visibility is looked for from four of its elements, one per quadrant about its
// centroid: the open one (open_share at least a half) nearest the centroid of the
// quadrant's open area; a quadrant with none repeats another's.
void HemicubeFormFactors::find_lookouts(std::span<const double> open) {
  auto open_at = [&](std::uint32_t i) { return open.empty() ? 1.0 : open[i]; };
  for (std::uint32_t g = 0; g < mesh_.groups.size(); ++g) {
    const ElementGroup& group = mesh_.groups[g];
    if (group.count < 2) continue;
    const Frame frame = frame_about(group.normal);
    auto quadrant = [&](std::uint32_t i) {
      const Vec3 d = frame.to_local(mesh_.elements[i].centroid - group.centroid);
      return std::size_t((d.x < 0 ? 0 : 1) + (d.y < 0 ? 0 : 2));
    };
    std::array<Vec3, 4> centre{};
    std::array<double, 4> area{};
    for (std::uint32_t i = group.first; i < group.first + group.count; ++i) {
      grouped_[i] = true;
      const double open_area = mesh_.elements[i].area * open_at(i);
      centre[quadrant(i)] += open_area * mesh_.elements[i].centroid;
      area[quadrant(i)] += open_area;
    }
    std::array<std::uint32_t, 4> lookout;
    lookout.fill(group.first);
    std::array<double, 4> best;
    best.fill(INFINITY);
    for (std::uint32_t i = group.first; i < group.first + group.count; ++i) {
      const std::size_t q = quadrant(i);
      if (open_at(i) < 0.5) continue;
      const double d = glm::length(mesh_.elements[i].centroid - centre[q] / area[q]);
      if (d < best[q]) best[q] = d, lookout[q] = i;
    }
    for (std::size_t q = 0; q < 4; ++q)
      if (!std::isfinite(best[q]))
        for (std::size_t r = 0; r < 4; ++r)
          if (std::isfinite(best[r])) lookout[q] = lookout[r];
    std::sort(lookout.begin(), lookout.end());
    group_radius_.push_back(run_radius(mesh_, group));
    groups_.push_back(g);
    first_lookout_.push_back(std::uint32_t(lookouts_.size()));
    lookouts_.insert(lookouts_.end(), lookout.begin(), std::unique(lookout.begin(), lookout.end()));
  }
}

// Each grouped element blends the visibility of the four lookouts nearest it on its surface
// (facing within 60 degrees of it, its own group's or its neighbours'), weighed by a tent
// (1 - d / r)^2 whose radius r is the fifth's distance, so that a lookout's weight falls to
// zero as it leaves the four: a shadow's edge then runs across a group as the elements see
// it, and on into the next group without a seam, not in steps of a group (on a penumbra two
// groups wide: 9.3 % RMS per element with one value a group, 1.7 % blended; the tent, the
// inverse distance and its square all came within 0.1 % of that). Its own group's lookouts
// stand in where none lie near enough.
void HemicubeFormFactors::blend_lookouts(std::stop_token stop) {
  first_lookout_.push_back(std::uint32_t(lookouts_.size()));
  std::vector<double> sides;
  for (std::uint32_t g : groups_) sides.push_back(std::sqrt(mesh_.groups[g].area));
  if (sides.empty()) return;
  std::nth_element(sides.begin(), sides.begin() + sides.size() / 2, sides.end());
  const double cell = std::max(sides[sides.size() / 2], 1e-9);
  auto cell_of = [&](const Vec3& p) { return glm::ivec3(glm::floor(p / cell)); };
  auto key = [](const glm::ivec3& c) {
    return (std::uint64_t(std::uint32_t(c.x) & 0x1FFFFF) << 42) |
           (std::uint64_t(std::uint32_t(c.y) & 0x1FFFFF) << 21) |
           std::uint64_t(std::uint32_t(c.z) & 0x1FFFFF);
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  for (std::uint32_t l = 0; l < lookouts_.size(); ++l)
    grid[key(cell_of(mesh_.elements[lookouts_[l]].centroid))].push_back(l);

  for (std::uint32_t g : groups_) {
    first_blend_.push_back(std::uint32_t(blends_.size()));
    blends_.resize(blends_.size() + mesh_.groups[g].count);
  }
  parallel_for(
      int(groups_.size()),
      [&](int k) {
        const ElementGroup& group = mesh_.groups[groups_[std::size_t(k)]];
        const double radius = 1.5 * std::sqrt(group.area);
        // The lookouts within reach of any of the group's elements, found once a group.
        double extent = 0;
        for (std::uint32_t j = group.first; j < group.first + group.count; ++j)
          extent = std::max(extent, glm::length(mesh_.elements[j].centroid - group.centroid));
        const int reach = std::min(3, int(std::ceil((extent + radius) / cell)));
        const glm::ivec3 c = cell_of(group.centroid);
        std::vector<std::uint32_t> candidates;
        for (int dx = -reach; dx <= reach; ++dx)
          for (int dy = -reach; dy <= reach; ++dy)
            for (int dz = -reach; dz <= reach; ++dz)
              if (auto it = grid.find(key(c + glm::ivec3(dx, dy, dz))); it != grid.end())
                candidates.insert(candidates.end(), it->second.begin(), it->second.end());
        std::vector<std::pair<double, std::uint32_t>> near;
        for (std::uint32_t j = group.first; j < group.first + group.count; ++j) {
          const Element& e = mesh_.elements[j];
          near.clear();
          for (std::uint32_t l : candidates) {
            const Element& o = mesh_.elements[lookouts_[l]];
            const double d = glm::length(o.centroid - e.centroid);
            if (o.surface == e.surface && glm::dot(o.normal, e.normal) > 0.5 && d < radius)
              near.push_back({d, l});
          }
          Blend& b = blends_[first_blend_[std::size_t(k)] + j - group.first];
          if (near.empty()) {
            const std::uint32_t first = first_lookout_[std::size_t(k)];
            for (std::uint32_t l = first; l < first_lookout_[std::size_t(k) + 1]; ++l)
              b.lookout[l - first] = l, b.weight[l - first] = 1;
            continue;
          }
          const std::size_t n = std::min<std::size_t>(near.size(), 5);
          std::partial_sort(near.begin(), near.begin() + std::ptrdiff_t(n), near.end());
          // A hair past the fifth, so that lookouts all as far keep a weight.
          const double r = 1.0001 * (n == 5 ? near[4].first : radius) + 1e-12;
          for (std::size_t i = 0; i < std::min<std::size_t>(n, 4); ++i) {
            b.lookout[i] = near[i].second;
            b.weight[i] = float((r - near[i].first) * (r - near[i].first) / (r * r));
          }
        }
      },
      stop);
}

// Neither the aliasing receivers, the groups' rays nor their unoccluded form factors depend
// on the hemi-cube: they are found on another thread while it renders (llvmpipe renders on
// one).
void HemicubeFormFactors::begin(const Shot& shot) {
  near_points(shot);
  if (!rays_) return;
  rays_->weigh(shot.patch, shot.weight);
  prepared_ = std::async(std::launch::async, [this, shot] { return prepare(shot); });
}

HemicubeFormFactors::Prepared HemicubeFormFactors::prepare(const Shot& shot) const {
  Prepared out;
  by_rays(shot, out);
  out.grouped = grouped(shot);
  return out;
}

// The points near_lambert() spreads over the shooter: its elements' quarter points, each
// with its share of the element's power, or, past kNearFieldPoints, binned (spread_points).
void HemicubeFormFactors::near_points(const Shot& shot) {
  const Patch& patch = mesh_.patches[shot.patch];
  near_points_ = spread_points(mesh_, patch, shot.weight, open_, kNearFieldPoints, 2);
  near_frame_ = frame_about(patch.normal);
  near_curved_ = curved(mesh_, patch);
  near_lo_ = glm::dvec2(std::numeric_limits<double>::max());
  near_hi_ = -near_lo_;
  for (const AreaSample& s : near_points_) {
    const Vec3 d = s.point - patch.centroid;
    const glm::dvec2 at(glm::dot(d, near_frame_.x), glm::dot(d, near_frame_.y));
    near_lo_ = glm::min(near_lo_, at);
    near_hi_ = glm::max(near_hi_, at);
  }
}

// Near field (docs/architecture.md; Baum, Rushmeier & Winget 1989): one hemi-cube at the
// patch centre misjudges receivers within a few patch sizes, by +20% for parallel unit
// squares one unit apart. Keep the hemi-cube's visible fraction of the receiver, but take
// its unoccluded form factor as the mean of the exact point-to-polygon values (Lambert)
// over points spread across the shooting patch. The fraction is capped at 1 for the
// receiver's value; uncapped (its pixels' errors either way) for the total that find() keeps:
// capped, the total of 200 receivers at grazing angles came out 6 % short.
HemicubeFormFactors::NearValue HemicubeFormFactors::near_field(const Shot& shot,
                                                               std::uint32_t element,
                                                               double hemicube_form_factor) const {
  std::array<Vec3, 4> storage;
  const double at_origin =
      point_to_polygon(shot.origin, mesh_.patches[shot.patch].normal,
                       element_corners(mesh_, mesh_.elements[element], storage));
  const double unoccluded = at_origin > 0 ? near_lambert(element, false) : -1;
  if (!(unoccluded >= 0)) return {hemicube_form_factor, hemicube_form_factor};
  const double uncapped = hemicube_form_factor / at_origin * unoccluded;
  return {std::min(uncapped, unoccluded), uncapped};
}

// The mean of Lambert's values over the shooter's points (near_points()), each counting with
// the power it stands for: a patch lit at one end sends its near neighbours the light of that
// end. Each point faces as its elements do (bumprad-bench-scale's hills, 10k triangles, with
// the patch's mean normal instead: 10.2 % off the path tracer, not 9.5 %). Points behind the
// receiver count nothing (a floor under a box sees only the back of its sides); with
// `occluded`, nor do those a shadow ray from the receiver's centre does not reach.
// -1 if the shooter shoots nothing.
double HemicubeFormFactors::near_lambert(std::uint32_t element, bool occluded) const {
  const Element& e = mesh_.elements[element];
  const double radius = element_radius(mesh_, e);
  const double offset = centroid_ray_offset(mesh_);
  const Vec3 from = e.centroid + e.normal * offset;
  double mean = 0, weights = 0;
  for (const auto& [point, w, normal] : near_points_) {
    weights += w;
    if (glm::dot(e.normal, point - e.centroid) <= offset) continue;  // behind, or in its plane
    const double f = point_to_element(mesh_, e, radius, point, normal);
    if (!(f > 0)) continue;
    if (occluded) {
      const Vec3 path = point + normal * offset - from;
      const double length = glm::length(path);
      if (length > 0 && scene_rays_->occluded({from, path / length}, length)) continue;
    }
    mean += w * f;
  }
  return weights > 0 ? mean / weights : -1;
}

// Whether element `e`, `d` away from the hemi-cube (from it to the centroid), facing it, is
// expected to cover fewer than alias_pixels of its pixels: its solid angle A cos / r^2
// against a top face pixel's (2/R)^2 of the unit hemi-cube. Such a receiver falls between
// pixels, seen in a whole pixel or not at all (one no pixel sees got nothing), so its form
// factor comes from rays.
bool HemicubeFormFactors::between_pixels(const Element& e, const Vec3& d) const {
  const double r2 = glm::dot(d, d), r_cos = -glm::dot(e.normal, d);
  return r_cos > 0 && e.area * r_cos / (r2 * std::sqrt(r2)) <
                          alias_pixels_ * 4.0 / (double(resolution_) * double(resolution_));
}

// The receivers within the near field (hidden_near() takes those the hemi-cube misses),
// and the aliasing receivers (between_pixels()) with their form factors from rays. Grouped
// elements are left to grouped().
void HemicubeFormFactors::by_rays(const Shot& shot, Prepared& out) const {
  const std::uint32_t pi = shot.patch;
  const Patch& patch = mesh_.patches[pi];
  const double near = near_field_radius(patch);
  for (std::uint32_t j = 0; j < mesh_.elements.size(); ++j) {
    const Element& e = mesh_.elements[j];
    const Vec3 d = e.centroid - patch.centroid;
    if (e.patch == pi || grouped_[j]) continue;
    if (glm::dot(patch.normal, d) > 0 && between_pixels(e, d))
      out.aliased.push_back({j, 0});
    else if (glm::length(d) < near)
      out.near.push_back(j);
  }
  parallel_for(
      int(out.aliased.size()),
      [&](int k) {
        VisibleElement& s = out.aliased[std::size_t(k)];
        s.form_factor = rays_->form_factor(pi, s.element);
      },
      shot.stop);
}

// Near receivers the hemi-cube did not see: it looks from the patch centre only, and a
// patch beside a box sees faces of it from parts the centre does not (the floor of a room
// with boxes standing on it, in 0.8 m patches of its fine triangles: 5.9 % off against the
// path tracer, 4.6 % with these). Lambert's value from each of the shooter's quarter points
// that the receiver sees: a point's value and its view go together (Lambert's mean times
// the share of 64 samples seen was 18 % short beside a block, whose nearest points are the
// ones in view).
std::vector<VisibleElement> HemicubeFormFactors::hidden_near(
    const Shot& shot, std::span<const std::uint32_t> near) const {
  std::vector<VisibleElement> out;
  for (std::uint32_t j : near)
    if (visible_slot_[j] < 0) out.push_back({j, 0});
  parallel_for(
      int(out.size()),
      [&](int k) {
        VisibleElement& s = out[std::size_t(k)];
        s.form_factor = std::max(0.0, near_lambert(s.element, true));
      },
      shot.stop);
  return out;
}

// Groups of a model's small triangles (mesh.h), each too small for the hemi-cube's pixels:
// alone each would get a whole pixel or none, and 16 rays apiece (the aliasing fallback) had
// cost 0.27 s a shot on a 100,000-triangle floor. Each element gets its unoccluded form
// factor (the rays' formula, every sample in view), which varies smoothly across the
// group, times the visible share of the shooter blended from the rays of the lookouts near
// it. The group's pixels would give that share too, but noisily: at 14 pixels a group they
// were 9 % off (RMS per element), the rays 0.05 %. Per shot this costs one pass over the
// grouped elements and 64 rays a group, whatever the triangles. The shooter's own groups
// receive too: a curved patch's triangles that face each other (a valley) light each other,
// and a closed room of hills left out that light, 16 % short in its valleys.
std::vector<VisibleElement> HemicubeFormFactors::grouped(const Shot& shot) const {
  const std::vector<double> seen = lookout_views(shot.stop);
  std::vector<std::vector<VisibleElement>> per_group(groups_.size());
  parallel_for(
      int(groups_.size()),
      [&](int k) {
        const ElementGroup& group = mesh_.groups[groups_[std::size_t(k)]];
        const double radius = group_radius_[std::size_t(k)];
        std::vector<VisibleElement>& out = per_group[std::size_t(k)];
        // The field is fitted, and each unoccluded value found, only where some of the
        // shooter is in view: behind a hill, or facing away, nothing is owed.
        std::optional<PatchRays::Field> field;
        bool tried = false;  // the field, once some element sees the shooter
        for (std::uint32_t j = group.first; j < group.first + group.count; ++j) {
          const double visible = blended_view(std::size_t(k), j, seen);
          if (!(visible > 0)) continue;
          if (!tried && group.count > kFieldElements &&
              beyond_near_points(shot, group.centroid) > radius)
            field = rays_->unoccluded_field(shot.patch, group, radius);
          tried = true;
          const std::optional<double> from_field =
              field ? (*field)(mesh_.elements[j]) : std::nullopt;
          const double f = (from_field ? *from_field : grouped_unoccluded(shot, j)) *
                           (open_ ? open_->share[j] : 1);
          if (f > 0) out.push_back({j, f * visible});
        }
      },
      shot.stop);
  std::vector<VisibleElement> all;
  for (const auto& g : per_group) all.insert(all.end(), g.begin(), g.end());
  return all;
}

std::vector<double> HemicubeFormFactors::lookout_views(std::stop_token stop) const {
  std::vector<double> seen(lookouts_.size());
  parallel_for(
      int(lookouts_.size()),
      [&](int l) {
        seen[std::size_t(l)] =
            rays_->visible_share(lookouts_[std::size_t(l)], PatchRays::Samples::Lookout);
      },
      stop);
  return seen;
}

double HemicubeFormFactors::blended_view(std::size_t k, std::uint32_t j,
                                         std::span<const double> seen) const {
  const Blend& b = blends_[first_blend_[k] + j - mesh_.groups[groups_[k]].first];
  double visible = 0, weights = 0;
  for (std::size_t i = 0; i < 4; ++i)
    if (b.weight[i] > 0 && !std::isnan(seen[b.lookout[i]]))
      visible += b.weight[i] * seen[b.lookout[i]], weights += b.weight[i];
  return weights > 0 ? visible / weights : 0;
}

std::vector<VisibleElement>& HemicubeFormFactors::find(const Shot& shot, Hemicube& hemicube, bool) {
  const Patch& patch = mesh_.patches[shot.patch];
  // Grouped elements take their light from grouped() instead of their pixels.
  visible_ = hemicube.form_factors();
  double rendered = 0, grouped_pixels = 0;
  for (const VisibleElement& v : visible_) {
    rendered += v.form_factor;
    if (grouped_[v.element]) grouped_pixels += v.form_factor;
  }
  std::erase_if(visible_, [&](const VisibleElement& v) { return grouped_[v.element]; });
  double seen = 0;
  for (std::size_t k = 0; k < visible_.size(); ++k) {
    visible_slot_[visible_[k].element] = std::int32_t(k);
    seen += visible_[k].form_factor;
  }
  std::vector<std::size_t> close;
  double seen_near = 0;
  for (std::size_t k = 0; k < visible_.size(); ++k)
    if (glm::length(mesh_.elements[visible_[k].element].centroid - patch.centroid) <
        near_field_radius(patch)) {
      close.push_back(k);
      seen_near += visible_[k].form_factor;
    }
  std::vector<double> uncapped(close.size());
  parallel_for(
      int(close.size()),
      [&](int k) {
        VisibleElement& v = visible_[close[std::size_t(k)]];
        const NearValue near = near_field(shot, v.element, v.form_factor);
        v.form_factor = near.form_factor;
        uncapped[std::size_t(k)] = near.uncapped;
      },
      shot.stop);
  // What was prepared while the hemi-cube rendered: near receivers it did not see, the
  // aliasing receivers and the groups.
  const Prepared prepared = prepared_.valid() ? prepared_.get() : Prepared{};
  // The shooter's own groups (a curved patch's triangles lighting each other) are not in
  // its hemi-cube, which does not draw the shooter.
  double grouped_rays = 0, others_rays = 0;
  for (const VisibleElement& v : prepared.grouped) {
    grouped_rays += v.form_factor;
    if (mesh_.elements[v.element].patch != shot.patch) others_rays += v.form_factor;
  }
  double corrected = 0;
  for (const VisibleElement& v : visible_) corrected += v.form_factor;
  const double corrected_near = std::accumulate(uncapped.begin(), uncapped.end(), 0.0);
  // What the near field adds to its receivers over the centre's view, the rest of the
  // patch's hemisphere gives up: the far receivers and the void, in the shares the centre
  // sees them. Only the void's part changes the total; the far receivers' part is
  // redistributed (all receivers scaled alike). A closed room (no void) keeps the
  // hemi-cube's total, so no energy is made or lost; an open scene of near receivers alone
  // takes the near field's own total (kept as rendered, two parallel 2 x 1 m plates 1 m
  // apart got 26 % too much: the floor's edges see less of the ceiling than its centre).
  // The groups' rays, from the whole patch, likewise move light to or from the rest: a
  // floor patch whose centre lies under a ball on it saw the ball in 84 % of its hemi-cube
  // where the rays found 26 %, and the 58 % between was lost (a closed room of balls let 9 %
  // of its light escape; the scale bench's closed terrain 0.8 %, which left it 2 % dark).
  const double kept = kept_light(rendered, seen, seen - seen_near, corrected_near - seen_near,
                                 grouped_rays - grouped_pixels);
  const double scale = corrected > 0 ? kept / corrected : 0;
  for (VisibleElement& v : visible_) v.form_factor *= scale;

  for (const VisibleElement& s : hidden_near(shot, prepared.near))
    if (s.form_factor > 0) visible_.push_back(s);
  for (const VisibleElement& s : prepared.aliased) {
    if (visible_slot_[s.element] >= 0)
      visible_[std::size_t(visible_slot_[s.element])].form_factor = s.form_factor;
    else if (s.form_factor > 0)
      visible_.push_back(s);
  }
  for (const VisibleElement& v : visible_) visible_slot_[v.element] = -1;
  if (rays_ && !near_curved_ && std::abs(grouped_pixels - others_rays) > kCentreDisagreement)
    share_by_rays(shot);
  visible_.insert(visible_.end(), prepared.grouped.begin(), prepared.grouped.end());
  at_most_one(visible_);
  return visible_;
}

// A cluster's shot: its pixels from two half hemi-cubes at its centre, the rays' receivers
// found meanwhile, the light balanced as a patch's shot balances it. No near field: the
// point is exact for a uniformly bright ball wherever a receiver sees all of it, as a
// floor does even where the ball touches it.
std::vector<std::vector<VisibleElement>> HemicubeFormFactors::find(
    const Cluster& cluster, std::span<const std::vector<Vec3>> lobes, const Frame& frame,
    Hemicube& hemicube, std::stop_token stop) {
  const std::size_t members = lobes.size();
  std::future<ClusterRays> rays;
  if (rays_) {
    rays_->weigh(cluster);
    rays = std::async(std::launch::async, [&] { return cluster_rays(cluster, lobes, stop); });
  }
  std::vector<std::vector<VisibleElement>> out(members);
  std::vector<double> rendered(members, 0), grouped_pixels(members, 0);
  for (const Frame& half : {frame, Frame{frame.x, -frame.y, -frame.z}}) {
    hemicube.render(cluster.centre, half, std::nullopt);
    for (std::size_t m = 0; m < members; ++m) {
      std::vector<Vec3> local;
      for (const Vec3& lobe : lobes[m]) local.push_back(half.to_local(lobe));
      for (const VisibleElement& v : hemicube.form_factors(local)) {
        rendered[m] += v.form_factor;
        if (grouped_[v.element])
          grouped_pixels[m] += v.form_factor;
        else
          out[m].push_back(v);
      }
    }
  }
  ClusterRays found = rays.valid() ? rays.get() : ClusterRays{};
  found.aliased.resize(members);
  found.grouped.resize(members);
  for (std::size_t m = 0; m < members && !stop.stop_requested(); ++m) {
    std::vector<VisibleElement> merged;  // an element seen in both halves sums its pixels
    for (const VisibleElement& v : out[m]) {
      std::int32_t& slot = visible_slot_[v.element];
      if (slot < 0) {
        slot = std::int32_t(merged.size());
        merged.push_back(v);
      } else {
        merged[std::size_t(slot)].form_factor += v.form_factor;
      }
    }
    double seen = 0, grouped_rays = 0;
    for (const VisibleElement& v : merged) seen += v.form_factor;
    for (const VisibleElement& v : found.grouped[m]) grouped_rays += v.form_factor;
    const double kept = kept_light(rendered[m], seen, seen, 0, grouped_rays - grouped_pixels[m]);
    for (VisibleElement& v : merged) v.form_factor *= seen > 0 ? kept / seen : 0;
    for (const VisibleElement& s : found.aliased[m]) {
      if (visible_slot_[s.element] >= 0)
        merged[std::size_t(visible_slot_[s.element])].form_factor = s.form_factor;
      else if (s.form_factor > 0)
        merged.push_back(s);
    }
    for (const VisibleElement& v : merged) visible_slot_[v.element] = -1;
    merged.insert(merged.end(), found.grouped[m].begin(), found.grouped[m].end());
    at_most_one(merged);
    out[m] = std::move(merged);
  }
  return out;
}

// A cluster's aliasing receivers and groups, per member: the point's form factor
// (cluster_form_factor()) times the share of the cluster the receiver's rays, or its
// lookouts', see. The cluster's own elements receive nothing: it is convex.
HemicubeFormFactors::ClusterRays HemicubeFormFactors::cluster_rays(
    const Cluster& cluster, std::span<const std::vector<Vec3>> lobes, std::stop_token stop) const {
  const std::size_t members = lobes.size();
  ClusterRays out{std::vector<std::vector<VisibleElement>>(members),
                  std::vector<std::vector<VisibleElement>>(members)};
  std::vector<std::uint32_t> aliased;
  for (std::uint32_t j = 0; j < mesh_.elements.size(); ++j) {
    const Element& e = mesh_.elements[j];
    if (e.object != cluster.object && !grouped_[j] &&
        between_pixels(e, e.centroid - cluster.centre))
      aliased.push_back(j);
  }
  std::vector<double> view(aliased.size());
  parallel_for(
      int(aliased.size()),
      [&](int k) { view[std::size_t(k)] = rays_->visible_share(aliased[std::size_t(k)]); }, stop);
  for (std::size_t m = 0; m < members; ++m)
    for (std::size_t k = 0; k < aliased.size(); ++k) {
      const Element& e = mesh_.elements[aliased[k]];
      const double f =
          view[k] > 0 ? cluster_form_factor(mesh_, lobes[m], cluster.centre, e) * view[k] : 0;
      out.aliased[m].push_back({aliased[k], f});
    }

  const std::vector<double> seen = lookout_views(stop);
  std::vector<std::vector<std::vector<VisibleElement>>> per_group(groups_.size());
  parallel_for(
      int(groups_.size()),
      [&](int k) {
        const ElementGroup& group = mesh_.groups[groups_[std::size_t(k)]];
        if (mesh_.elements[group.first].object == cluster.object) return;
        auto& lists = per_group[std::size_t(k)];
        lists.resize(members);
        for (std::uint32_t j = group.first; j < group.first + group.count; ++j) {
          const double visible = blended_view(std::size_t(k), j, seen);
          if (!(visible > 0)) continue;
          const Element& e = mesh_.elements[j];
          const double open = open_ ? open_->share[j] : 1;
          for (std::size_t m = 0; m < members; ++m)
            if (const double f = cluster_form_factor(mesh_, lobes[m], cluster.centre, e); f > 0)
              lists[m].push_back({j, f * open * visible});
        }
      },
      stop);
  for (const auto& lists : per_group)
    for (std::size_t m = 0; m < lists.size(); ++m)
      out.grouped[m].insert(out.grouped[m].end(), lists[m].begin(), lists[m].end());
  return out;
}

// A patch's hemi-cube looks from its centre, and where a small object stands there (a ball
// on a floor patch) its view is not the patch's: the ball fills most of it, and the walls
// behind the ball go unseen. The groups' rays, spread over the whole patch, tell: where
// they and the groups' pixels disagree by more than kCentreDisagreement of the hemisphere,
// a flat patch's receivers share the total find() gave them as the patch's rays say, as
// ray casting would (the total stays: in a closed room all of the light, where rays alone
// lose a few per cent of it). bumprad-bench-scale's objects family (100 balls on a floor)
// with its floor in 0.1 m elements: 6.4 % off the path tracer with the centre's view (the
// light it gave the balls beyond their rays moved to what it saw past them, the walls'
// lower halves), 2.5 % this way; at its defaults 3.32 -> 3.08 %, the room family 1.67 ->
// 1.62 %. A curved patch keeps its centre's view: its centroid lies off its surface, its
// pixels and rays differ by design, and rays there took the terrain family 1.16 -> 1.34 %.
// Below the threshold the centre's shares stay, and can be off: a 0.3 m ball 0.28 m from
// the centre of a 0.5 m patch leaves the ceiling 16 % short of 64 hemi-cubes' mean.
void HemicubeFormFactors::share_by_rays(const Shot& shot) {
  double total = 0;
  for (const VisibleElement& v : visible_) total += v.form_factor;
  std::vector<double> f(mesh_.elements.size(), 0.0);
  parallel_for(
      int(f.size()),
      [&](int j) {
        if (!grouped_[std::size_t(j)])
          f[std::size_t(j)] = rays_->form_factor(shot.patch, std::uint32_t(j));
      },
      shot.stop);
  const double by_rays = std::accumulate(f.begin(), f.end(), 0.0);
  visible_.clear();
  if (!(by_rays > 0)) return;
  for (std::uint32_t j = 0; j < f.size(); ++j)
    if (f[j] > 0) visible_.push_back({j, f[j] * total / by_rays});
}

// A grouped element's form factor were nothing in the way. Close to a large shooter (within
// two spacings of the rays' samples of the rectangle its near points span), the rays' few
// point samples misjudge it: Lambert's values from the near points instead (near_lambert()).
// A room's box faces standing on 0.8 m patches of floor triangles came out 20 % dark at their
// feet from the samples alone (the room at 10k triangles: 4.4 % off the path tracer, 3.2 %
// with this), while checking all receivers within the near field (2.4 m there) doubled the
// solve for 0.1 % more.
double HemicubeFormFactors::grouped_unoccluded(const Shot& shot, std::uint32_t element) const {
  const Patch& patch = mesh_.patches[shot.patch];
  const Element& e = mesh_.elements[element];
  // A receiver facing as a flat shooter does, or behind its plane, sees little of it
  // (nothing in one plane) either way; about a curved one (a hill) it sees its flanks.
  if (beyond_near_points(shot, e.centroid) < 0 &&
      (near_curved_ || glm::dot(e.normal, patch.normal) < kSameFacing) &&
      (near_curved_ || glm::dot(e.centroid - patch.centroid, near_frame_.z) > 0))
    return std::max(0.0, near_lambert(element, false));
  return rays_->unoccluded(shot.patch, element);
}

// How far `at` lies beyond the reach of the shooter's near points: two spacings of its ray
// samples from the rectangle the near points span on its plane; negative within it, and
// infinite for a shooter that takes no near points (kExactElements or fewer elements).
double HemicubeFormFactors::beyond_near_points(const Shot& shot, const Vec3& at) const {
  const Patch& patch = mesh_.patches[shot.patch];
  if (patch.count <= kExactElements || near_points_.empty()) return INFINITY;
  const Vec3 d = at - patch.centroid;
  const glm::dvec2 in_plane(glm::dot(d, near_frame_.x), glm::dot(d, near_frame_.y));
  const glm::dvec2 out =
      glm::max(glm::max(near_lo_ - in_plane, in_plane - near_hi_), glm::dvec2(0));
  const double height = glm::dot(d, near_frame_.z);
  const double reach = 2 * std::sqrt(patch.area / double(kRaySamples));
  return std::sqrt(glm::dot(out, out) + height * height) - reach;
}

}  // namespace

std::unique_ptr<ShotFormFactors> make_shot_form_factors(const Mesh& mesh,
                                                        const SolverSettings& settings,
                                                        const RayScene* rays, const OpenParts* open,
                                                        std::stop_token stop) {
  if (settings.form_factors == FormFactorMethod::RayCast) {
    if (!rays) throw std::invalid_argument("ray-cast form factors need the mesh's RayScene");
    return std::make_unique<RayCastFormFactors>(mesh, *rays, open);
  }
  return std::make_unique<HemicubeFormFactors>(mesh, settings, rays, open, stop);
}

}  // namespace bumprad
