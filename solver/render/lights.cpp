#include "solver/render/lights.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include <glm/geometric.hpp>

#include "solver/radiosity/form_factor_exact.h"
#include "solver/scene/geometry.h"

namespace bumprad {
namespace {

// The part of a running sum `cumulative` (increasing, its last entry the whole) that t falls
// in, and where in it, from 0 to 1: how one number picks an element by area, or a source by
// its share, and goes on to place a point in it.
std::pair<std::size_t, double> pick(std::span<const double> cumulative, double t) {
  const std::size_t k = std::min(
      std::size_t(std::upper_bound(cumulative.begin(), cumulative.end(), t) - cumulative.begin()),
      cumulative.size() - 1);
  const double below = k > 0 ? cumulative[k - 1] : 0;
  return {k, std::clamp((t - below) / (cumulative[k] - below), 0.0, 1.0)};
}

// direct() takes an emitter group whole from this many times its radius away, element by
// element nearer.
constexpr double kGroupReach = 8;

// Whether a point lies in a penumbra is probed first with shadow rays to the centre and to
// the corners of the convex hull of each emitter surface it sees (make_probe_sets()): the
// straight edge of an occluder that covers any part of an emitter covers one of them,
// however small the part. The first of a few stratified points, which decided it before,
// left a band along every penumbra's edges read as wholly lit or wholly dark (the part that
// no point fell in): cornell at 256 x 256, 4 x 4 rays a pixel and 7,804 elements was 1.05 %
// off a 2,048-path reference with 4 first points, 0.78 % with 8, 0.79 % with the probes.
// Points that the probes tell are wholly lit (or dark) take the exact value; the others
// cast kPenumbraRays times ShadowRays::count stratified rays. The corners are pulled
// kProbeInset of the way toward the centre, off the creases a lamp may share with a ceiling
// or wall.
constexpr int kPenumbraRays = 4;
constexpr double kProbeInset = 0.01;
// Probes cost five rays or more a surface: beyond this many surfaces (and images) a point
// sees, the rest are taken as penumbrae, their light from stratified rays.
constexpr std::size_t kProbedSets = 4;

// The index in the sequence of a hit's ray r, `block` rays a hit: the hit's own block of the
// first hits x block points, so that the rays of a pixel whose hits all lie in a penumbra are
// one net.
std::uint32_t ray_index(const ShadowRays& shadow, std::uint32_t block, std::uint32_t r) {
  return shadow.hit * block + r;
}

// Veach's power heuristic: the weight of a sample drawn with density `a` where another
// strategy would have drawn it with density `b`.
double power_heuristic(double a, double b) {
  return a * a / (a * a + b * b);
}

}  // namespace

Lights::Lights(const Mesh& mesh, std::span<const Material> materials,
               std::span<const PunctualLight> punctual)
    : mesh_(mesh),
      mirrors_(planar_mirror_planes(mesh, materials)),
      punctual_(punctual_sources(punctual, mirrors_)),
      epsilon_(ray_epsilon(mesh)) {
  double total = 0;
  for (std::uint32_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    const Rgb& emission = materials[std::size_t(e.material)].emission;
    const double weight = emission.r + emission.g + emission.b;
    if (!(weight * e.area > 0)) continue;
    total += weight * e.area;
    emitters_.push_back({i, emission, weight});
    cumulative_.push_back(total);
  }
  for (double& c : cumulative_) c /= total;
  total_power_ = total;
  group_emitters();
}

void Lights::group_emitters() {
  std::map<std::pair<std::uint32_t, int>, std::vector<std::uint32_t>> by_patch;
  for (const Emitter& em : emitters_) {
    const Element& e = mesh_.elements[em.element];
    by_patch[{e.patch, e.material}].push_back(em.element);
  }
  for (auto& [key, elements] : by_patch) {
    const Element& first = mesh_.elements[elements.front()];
    const Emitter& em =
        *std::lower_bound(emitters_.begin(), emitters_.end(), elements.front(),
                          [](const Emitter& a, std::uint32_t i) { return a.element < i; });
    auto add = [&](std::vector<std::uint32_t> members, std::vector<Vec3> outline) {
      Group g{std::move(outline),
              std::move(members),
              {},
              em.emission,
              em.weight,
              first.centroid,
              first.normal,
              Vec3(0),
              0};
      double area = 0;
      for (std::uint32_t i : g.elements) {
        g.cumulative.push_back(area += mesh_.elements[i].area);
        g.centre += mesh_.elements[i].area * mesh_.elements[i].centroid;
      }
      g.centre /= area;
      for (double& c : g.cumulative) c /= area;
      for (const Vec3& c : g.outline) g.radius = std::max(g.radius, glm::length(c - g.centre));
      groups_.push_back(std::move(g));
    };
    std::vector<Vec3> outline = planar_outline(elements);
    if (!outline.empty()) {
      add(elements, std::move(outline));
      continue;
    }
    for (std::uint32_t i : elements) {  // curved, or not one simple region: one by one
      const Element& e = mesh_.elements[i];
      std::array<Vec3, 4> storage;
      const std::span<const Vec3> corners = element_corners(mesh_, e, storage);
      add({i}, std::vector<Vec3>(corners.begin(), corners.end()));
    }
  }
  make_probe_sets();
}

// The groups of one flat emitter surface share one probe set, the corners of their convex
// hull in its plane (a straight occluding edge that covers any of the surface covers one of
// them) pulled toward its centre, and the centre; a group of a curved one has its own.
void Lights::make_probe_sets() {
  std::map<std::pair<std::uint32_t, int>, std::vector<std::size_t>> by_surface;
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    const Element& e = mesh_.elements[groups_[g].elements.front()];
    by_surface[{e.surface, e.material}].push_back(g);
  }
  for (const auto& [key, members] : by_surface) {
    std::vector<std::uint32_t> elements;
    for (std::size_t g : members)
      elements.insert(elements.end(), groups_[g].elements.begin(), groups_[g].elements.end());
    if (members.size() > 1 && !coplanar(mesh_, elements, kOnePlane)) {
      for (std::size_t g : members) add_probe_set({&g, 1}, groups_[g].outline);
      continue;
    }
    std::vector<Vec3> corners;
    for (std::size_t g : members)
      corners.insert(corners.end(), groups_[g].outline.begin(), groups_[g].outline.end());
    add_probe_set(members, convex_hull(corners, groups_[members.front()].normal));
  }
}

void Lights::add_probe_set(std::span<const std::size_t> members, std::span<const Vec3> corners) {
  Vec3 centre(0);
  double area = 0;
  for (std::size_t g : members)
    for (std::uint32_t i : groups_[g].elements) {
      centre += mesh_.elements[i].area * mesh_.elements[i].centroid;
      area += mesh_.elements[i].area;
    }
  std::vector<Vec3> points{centre / area};
  for (const Vec3& c : corners) points.push_back(c + kProbeInset * (points.front() - c));
  for (std::size_t g : members) groups_[g].probes = std::uint32_t(probe_sets_.size());
  probe_sets_.push_back(std::move(points));
}

std::vector<Vec3> Lights::planar_outline(std::span<const std::uint32_t> elements) const {
  if (!coplanar(mesh_, elements, kOnePlane)) return {};
  // The elements turn the same way: an edge inside the region appears once each way, an
  // edge of its outline once. Outline edges chain into one loop, or the region is not simple.
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::uint32_t i : elements) {
    const Element& e = mesh_.elements[i];
    for (int k = 0; k < e.vertex_count; ++k)
      edges.insert({e.v[std::size_t(k)], e.v[std::size_t((k + 1) % e.vertex_count)]});
  }
  std::map<std::uint32_t, std::uint32_t> next;
  for (const auto& [a, b] : edges)
    if (!edges.contains({b, a}) && !next.emplace(a, b).second) return {};
  if (next.empty()) return {};
  std::vector<Vec3> loop;
  std::uint32_t at = next.begin()->first;
  for (std::size_t steps = 0; steps < next.size(); ++steps) {
    loop.push_back(mesh_.vertices[at].position);
    at = next.at(at);
  }
  if (at != next.begin()->first) return {};
  // Corners only: points on a straight run of the outline add nothing.
  std::vector<Vec3> corners;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Vec3& before = loop[(i + loop.size() - 1) % loop.size()];
    const Vec3& after = loop[(i + 1) % loop.size()];
    if (glm::length(glm::cross(loop[i] - before, after - loop[i])) >
        1e-12 * glm::length(loop[i] - before) * glm::length(after - loop[i]))
      corners.push_back(loop[i]);
  }
  return corners.size() >= 3 ? corners : std::vector<Vec3>{};
}

Vec3 Lights::point_on(const Element& e, double u, double v) const {
  auto corner = [&](int c) { return mesh_.vertices[e.v[std::size_t(c)]].position; };
  // A quad is two triangles (planar and convex); u picks one by its area and, rescaled,
  // goes on to place the point in it.
  Vec3 a = corner(0), b = corner(1), c = corner(2);
  if (e.vertex_count == 4) {
    const double first =
        0.5 * glm::length(glm::cross(corner(1) - corner(0), corner(2) - corner(0))) / e.area;
    if (u < first) {
      u /= first;
    } else {
      u = (u - first) / (1 - first);
      b = corner(2), c = corner(3);
    }
  }
  const double s = std::sqrt(std::min(u, 1.0));
  return (1 - s) * a + s * (1 - v) * b + s * v * c;
}

Lights::Sample Lights::sample(Random& random) const {
  const double pick = random.next();
  const std::size_t i =
      std::min(std::size_t(std::lower_bound(cumulative_.begin(), cumulative_.end(), pick) -
                           cumulative_.begin()),
               emitters_.size() - 1);
  const Element& e = mesh_.elements[emitters_[i].element];
  const double chosen = cumulative_[i] - (i > 0 ? cumulative_[i - 1] : 0);
  const double u = random.next();
  return {emitters_[i].element, point_on(e, u, random.next()), chosen / e.area,
          emitters_[i].emission};
}

bool Lights::visible_through(const PlanarMirror& mirror, const Vec3& from, const Vec3& to_image,
                             const RayScene& rays) const {
  const Vec3 d = to_image - from;
  const double distance = glm::length(d);
  return mirror.shows(from, d / distance, distance, rays);
}

Rgb Lights::next_event(const Vec3& from, const Vec3& normal, const RayScene& rays,
                       Random& random) const {
  return punctual_direct(from, normal, from, rays) + area_next_event(from, normal, rays, random);
}

Rgb Lights::punctual_direct(const Vec3& x, const Vec3& normal, const Vec3& from,
                            const RayScene& rays) const {
  Rgb sum(0);
  for (const PunctualSource& l : punctual_) sum += punctual_irradiance(l, x, normal, from, rays);
  return sum;
}

Rgb Lights::area_next_event(const Vec3& from, const Vec3& normal, const RayScene& rays,
                            Random& random) const {
  if (emitters_.empty()) return Rgb(0);
  // One emitter point for the emitter and every mirror's image of it: each term below is
  // an unbiased estimate of its own integral, so their sum is one of the total.
  const Sample light = sample(random);
  const Element& le = mesh_.elements[light.element];
  const Rgb& emission = light.emission;
  auto term = [&](const Vec3& y, const Vec3& facing) {
    Vec3 d = y - from;
    const double distance2 = glm::dot(d, d);
    d /= std::sqrt(distance2);
    const double cos_here = glm::dot(normal, d), cos_there = -glm::dot(facing, d);
    if (cos_here <= 0 || cos_there <= 0) return 0.0;
    return cos_here * cos_there / (std::numbers::pi * distance2 * light.pdf_area);
  };
  Rgb sum(0);
  if (const double g = term(light.point, le.normal); g > 0) {
    const double distance = glm::length(light.point - from);
    if (!rays.occluded({from, (light.point - from) / distance}, distance - 2 * epsilon_))
      sum += emission * g;
  }
  for (const PlanarMirror& m : mirrors_) {
    if (!m.in_front(from) || !m.in_front(light.point)) continue;
    const Vec3 image = m.reflect(light.point);
    const Vec3 facing = m.turn(le.normal);
    if (const double g = term(image, facing); g > 0 && visible_through(m, from, image, rays))
      sum += emission * (m.specular * g);
  }
  return sum;
}

double Lights::pdf_solid_angle(std::uint32_t element, double distance, double cos_there) const {
  auto it = std::lower_bound(emitters_.begin(), emitters_.end(), element,
                             [](const Emitter& e, std::uint32_t i) { return e.element < i; });
  if (it == emitters_.end() || it->element != element || cos_there <= 0) return 0;
  return it->weight / total_power_ * distance * distance / cos_there;  // pdf_area r^2 / cos'
}

bool Lights::planar_mirror(std::uint32_t surface) const {
  return std::any_of(mirrors_.begin(), mirrors_.end(),
                     [&](const PlanarMirror& m) { return m.surface == surface; });
}

Rgb Lights::glossy_next_event(const Vec3& from, const Vec3& geometric, const PhongLobe& lobe,
                              const RayScene& rays, Random& random) const {
  if (emitters_.empty()) return Rgb(0);
  const Sample light = sample(random);
  const Element& le = mesh_.elements[light.element];
  // One term: the point y (or its image) seen along d at `distance`, facing `facing`.
  auto term = [&](const Vec3& y, const Vec3& facing, const PlanarMirror* mirror) {
    Vec3 d = y - from;
    const double distance = glm::length(d);
    d /= distance;
    if (glm::dot(d, geometric) <= 0) return 0.0;
    const double lobe_pdf = lobe.pdf(d);
    const double light_pdf = pdf_solid_angle(light.element, distance, -glm::dot(facing, d));
    if (lobe_pdf <= 0 || light_pdf <= 0) return 0.0;
    if (mirror ? !visible_through(*mirror, from, y, rays)
               : rays.occluded({from, d}, distance - 2 * epsilon_))
      return 0.0;
    return (mirror ? mirror->specular : 1) * lobe_pdf * power_heuristic(light_pdf, lobe_pdf) /
           light_pdf;
  };
  double sum = term(light.point, le.normal, nullptr);
  for (const PlanarMirror& m : mirrors_)
    if (m.in_front(from) && m.in_front(light.point))
      sum += term(m.reflect(light.point), m.turn(le.normal), &m);
  return light.emission * sum;
}

Rgb Lights::glossy_punctual(const Vec3& from, const Vec3& geometric, const PhongLobe& lobe,
                            const RayScene& rays) const {
  Rgb sum(0);
  for (const PunctualSource& l : punctual_) {
    const PunctualArrival a = punctual_arrival(l, from, geometric, from, rays);
    if (a.irradiance != Rgb(0)) sum += a.irradiance * (kPi * lobe.pdf(a.toward));
  }
  return sum;
}

double Lights::lobe_weight(double lobe_pdf, std::uint32_t element, double distance,
                           double cos_there) const {
  return power_heuristic(lobe_pdf, pdf_solid_angle(element, distance, cos_there));
}

// The emitters and their images that x sees in front of both planes, with their exact
// unoccluded F: a group whole, or near it (within kGroupReach of its radius) element by
// element, because shadow rays picked by area weigh a group's parts by area rather than by
// their form factors (whole, 1 m under a 1 m lamp half in shadow came out 2 % too dark).
// Returns the sum of their shares.
double Lights::seen_from(const Vec3& x, const Vec3& normal, std::vector<Seen>& seen) const {
  static constexpr double kWhole = 1;
  thread_local std::vector<Vec3> corners;
  seen.clear();
  double total = 0;
  auto consider = [&](const Group& g, std::span<const std::uint32_t> elements,
                      std::span<const double> cumulative, std::span<const Vec3> outline,
                      const PlanarMirror* mirror) {
    Vec3 point = g.point, facing = g.normal;
    corners.assign(outline.begin(), outline.end());
    if (mirror) {
      if (!mirror->in_front(point)) return;  // behind it
      point = mirror->reflect(point);
      facing = mirror->turn(facing);
      for (Vec3& c : corners) c = mirror->reflect(c);
    }
    if (glm::dot(facing, x - point) <= 0) return;  // behind the emitter: one-sided
    const double f = point_to_polygon(x, normal, corners);
    if (!(f > 0)) return;
    const double share = f * g.weight * (mirror ? mirror->specular : 1);
    seen.push_back({elements, cumulative, &g, mirror, f, share});
    total += share;
  };
  std::array<Vec3, 4> storage;
  auto consider_group = [&](const Group& g, const PlanarMirror* mirror) {
    const Vec3 centre = mirror ? mirror->reflect(g.centre) : g.centre;
    if (g.elements.size() == 1 || glm::length(x - centre) > kGroupReach * g.radius) {
      consider(g, g.elements, g.cumulative, g.outline, mirror);
      return;
    }
    for (std::size_t k = 0; k < g.elements.size(); ++k)
      consider(g, {&g.elements[k], 1}, {&kWhole, 1},
               element_corners(mesh_, mesh_.elements[g.elements[k]], storage), mirror);
  };
  for (const Group& g : groups_) consider_group(g, nullptr);
  for (const PlanarMirror& m : mirrors_)
    if (m.in_front(x))
      for (const Group& g : groups_) consider_group(g, &m);
  return total;
}

// A point of what `s` sees for (u, v) in [0,1)^2, uniform by area: u picks an element by
// area and, rescaled, goes on to place the point in it.
Vec3 Lights::point_on(const Seen& s, double u, double v) const {
  const auto [k, rest] = pick(s.cumulative, u);
  return point_on(mesh_.elements[s.elements[k]], rest, v);
}

// A shadow ray from `from` to the emitter point y (through the mirror, to y's image).
bool Lights::arrives(const Seen& s, const Vec3& from, const Vec3& geometric, const Vec3& y,
                     const RayScene& rays) const {
  Vec3 d = (s.mirror ? s.mirror->reflect(y) : y) - from;
  const double distance = glm::length(d);
  d /= distance;
  if (glm::dot(d, geometric) <= 0) return false;
  if (!s.mirror) return !rays.occluded({from, d}, distance - 2 * epsilon_);
  return visible_through(*s.mirror, from, from + d * distance, rays);
}

int Lights::probe(const Seen& s, const Vec3& from, const Vec3& geometric,
                  const RayScene& rays) const {
  const std::vector<Vec3>& points = probe_sets_[s.group->probes];
  const bool first = arrives(s, from, geometric, points.front(), rays);
  for (std::size_t k = 1; k < points.size(); ++k)
    if (arrives(s, from, geometric, points[k], rays) != first) return -1;
  return first ? 1 : 0;
}

void Lights::visible(const Vec3& x, const Vec3& from, const Vec3& geometric, const RayScene& rays,
                     const ShadowRays& shadow, std::vector<Visible>& out) const {
  thread_local std::vector<Seen> seen;
  thread_local std::vector<int> told;                  // probe() of each one's probe set
  thread_local std::vector<std::size_t> first, parts;  // its group's first in `seen`; its parts
  out.clear();
  const double total = seen_from(x, geometric, seen);
  if (seen.empty()) return;
  bool penumbra = false;
  told.assign(seen.size(), 0);
  first.assign(seen.size(), 0);
  parts.assign(seen.size(), 0);
  thread_local std::vector<std::pair<std::pair<std::uint32_t, const PlanarMirror*>, int>> sets;
  sets.clear();
  for (std::size_t k = 0; k < seen.size(); ++k) {
    const Seen& s = seen[k];
    // seen_from() lists a group's elements together.
    const bool same = k > 0 && seen[k - 1].group == s.group && seen[k - 1].mirror == s.mirror;
    first[k] = same ? first[k - 1] : k;
    parts[first[k]] += s.elements.size();
    const std::pair key(s.group->probes, s.mirror);
    auto set =
        std::find_if(sets.begin(), sets.end(), [&](const auto& e) { return e.first == key; });
    if (set == sets.end())
      set = sets.insert(sets.end(),
                        {key, sets.size() < kProbedSets ? probe(s, from, geometric, rays) : -1});
    told[k] = set->second;
    penumbra = penumbra || told[k] < 0;
  }
  // A group seen wholly, all its elements in front, is one source: Lambert's form factor to
  // its outline is the sum of its elements', and what the point keeps (DirectForm) is one
  // polygon instead of one an element.
  const auto whole = [&](std::size_t k) {
    if (told[k] <= 0) return;
    const Seen& s = seen[k];
    if (parts[first[k]] < s.group->elements.size()) {
      out.push_back({s, 1});
    } else if (first[k] == k) {
      Seen merged{s.group->elements, s.group->cumulative, s.group, s.mirror, 0, 0};
      for (std::size_t j = k; j < seen.size() && first[j] == k; ++j) {  // its parts, together
        merged.form_factor += seen[j].form_factor;
        merged.share += seen[j].share;
      }
      out.push_back({merged, 1});
    }
  };
  const int n = std::max(1, shadow.count) * kPenumbraRays;
  if (seen.size() <= std::size_t(n)) {
    // Few: each in a penumbra gets its own rays, to stratified points of it (Sobol02 over its
    // elements by area). A source's sequence is shifted by the pixel's scramble and the
    // source itself, so the hits of a pixel that see it share it.
    const int each = n / int(seen.size());
    for (std::size_t k = 0; k < seen.size(); ++k) {
      const Seen& s = seen[k];
      if (told[k] >= 0) {
        whole(k);
        continue;
      }
      const std::uint64_t source = (std::uint64_t(s.elements.front()) << 16) ^
                                   std::uint64_t(s.mirror ? s.mirror - mirrors_.data() + 1 : 0);
      const Sobol02 points(hash64(shadow.scramble ^ hash64(source)));
      int hits = 0;
      for (int r = 0; r < each; ++r) {
        const auto [u, v] = points[ray_index(shadow, std::uint32_t(each), std::uint32_t(r))];
        hits += arrives(s, from, geometric, point_on(s, u, v), rays);
      }
      if (hits > 0) out.push_back({s, double(hits) / each});
    }
    return;
  }
  if (!penumbra) {
    for (std::size_t k = 0; k < seen.size(); ++k) whole(k);
    return;
  }
  // Many, some in a penumbra: n rays stratified over them all by contribution (the first
  // coordinate runs along their shares, then on within the one it falls in); each ray that
  // arrives adds the step over its source's share, the chance it was chosen, to the source's
  // visible share.
  thread_local std::vector<double> reached;
  thread_local std::vector<std::size_t> slot;
  reached.clear();
  for (const Seen& s : seen) reached.push_back((reached.empty() ? 0 : reached.back()) + s.share);
  slot.assign(seen.size(), std::size_t(-1));
  const Sobol02 points(hash64(shadow.scramble));
  for (int r = 0; r < n; ++r) {
    const auto [u, v] = points[ray_index(shadow, std::uint32_t(n), std::uint32_t(r))];
    const auto [k, rest] = pick(reached, u * total);
    const Seen& s = seen[k];
    if (!arrives(s, from, geometric, point_on(s, rest, v), rays)) continue;
    if (slot[k] == std::size_t(-1)) {
      slot[k] = out.size();
      out.push_back({s, 0});
    }
    out[slot[k]].share += 1;  // rays, weighed below
  }
  for (Visible& v : out) v.share *= total / n / v.seen.share;
}

std::span<const Vec3> Lights::polygon(const Seen& s, std::vector<Vec3>& storage) const {
  if (s.elements.size() == s.group->elements.size()) {
    storage.assign(s.group->outline.begin(), s.group->outline.end());
  } else {
    std::array<Vec3, 4> corners;
    const auto c = element_corners(mesh_, mesh_.elements[s.elements.front()], corners);
    storage.assign(c.begin(), c.end());
  }
  if (s.mirror)
    for (Vec3& c : storage) c = s.mirror->reflect(c);
  return storage;
}

Rgb Lights::direct(const Vec3& x, const Vec3& normal, const Vec3& geometric, const RayScene& rays,
                   const ShadowRays& shadow) const {
  const Vec3 from = x + geometric * epsilon_;
  Rgb sum(0);
  for (const PunctualSource& l : punctual_) {
    const PunctualArrival a = punctual_arrival(l, x, geometric, from, rays);
    sum += a.irradiance * std::max(0.0, glm::dot(normal, a.toward));
  }
  thread_local std::vector<Visible> seen;
  thread_local std::vector<Vec3> corners;
  visible(x, from, geometric, rays, shadow, seen);
  for (const Visible& v : seen) {
    // The shares were judged by the geometric plane; on a flat surface unbumped F is theirs
    // (an interpolated normal there is the geometric one to within 1e-7 radians).
    const double f = glm::dot(normal, geometric) > 1 - 5e-15
                         ? v.seen.form_factor
                         : point_to_polygon(x, normal, polygon(v.seen, corners));
    sum += v.seen.group->emission * (f * v.share * (v.seen.mirror ? v.seen.mirror->specular : 1));
  }
  return sum;
}

void Lights::direct_sources(const Vec3& x, const Vec3& geometric, const RayScene& rays,
                            const ShadowRays& shadow, const SourceVisitor& visit) const {
  const Vec3 from = x + geometric * epsilon_;
  for (const PunctualSource& l : punctual_) {
    const PunctualArrival a = punctual_arrival(l, x, geometric, from, rays);
    if (a.irradiance != Rgb(0)) visit(a.irradiance, a.toward, {});
  }
  thread_local std::vector<Visible> seen;
  thread_local std::vector<Vec3> corners;
  visible(x, from, geometric, rays, shadow, seen);
  for (const Visible& v : seen)
    visit(v.seen.group->emission * (v.share * (v.seen.mirror ? v.seen.mirror->specular : 1)),
          Vec3(0), polygon(v.seen, corners));
}

DirectForm Lights::direct_form(const Vec3& x, const Vec3& geometric, const RayScene& rays,
                               const ShadowRays& shadow) const {
  DirectForm form;
  thread_local std::vector<Vec3> toward;  // unit directions to everything seen
  toward.clear();
  direct_sources(x, geometric, rays, shadow,
                 [&](const Rgb& weight, const Vec3& to, std::span<const Vec3> polygon) {
                   const Vec3 vector = polygon.empty() ? to : polygon_vector(x, polygon);
                   for (int c = 0; c < 3; ++c)
                     form.rows[std::size_t(c)] += glm::vec3(weight[c] * vector);
                   if (polygon.empty()) toward.push_back(to);
                   for (const Vec3& c : polygon) toward.push_back(glm::normalize(c - x));
                 });
  if (toward.empty()) return form;
  Vec3 axis(0);
  for (const Vec3& d : toward) axis += d;
  if (!(glm::length(axis) > 0)) {
    form.reach = 2;
    return form;
  }
  axis = glm::normalize(axis);
  double cosine = 1;  // of the cone's half-angle
  for (const Vec3& d : toward) cosine = std::min(cosine, glm::dot(axis, d));
  form.axis = glm::vec3(axis);
  // A little wider than the corners' cone, so that single precision never lets through an N
  // whose plane cuts a source.
  form.reach = cosine > 1e-3 ? float(std::sqrt(1 - cosine * cosine) + 1e-5) : 2.0f;
  return form;
}

}  // namespace bumprad
