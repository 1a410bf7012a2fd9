#include "solver/lights.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>

#include "solver/form_factor_exact.h"

namespace bumprad {

double ray_epsilon(const Mesh& mesh) {
  double extent = 0;
  for (int k = 0; k < 3; ++k)
    extent = std::max({extent, std::abs(mesh.bounds_min[k]), std::abs(mesh.bounds_max[k])});
  return 4e-6 * extent;
}

Lights::Lights(const Mesh& mesh, std::span<const Material> materials)
    : mesh_(mesh), epsilon_(ray_epsilon(mesh)) {
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
}

Vec3 Lights::point_on(const Element& e, Random& random) const {
  auto corner = [&](int c) { return mesh_.vertices[e.v[std::size_t(c)]].position; };
  // A quad is two triangles (planar and convex); each is picked by its area.
  Vec3 a = corner(0), b = corner(1), c = corner(2);
  if (e.vertex_count == 4) {
    const double first =
        0.5 * glm::length(glm::cross(corner(1) - corner(0), corner(2) - corner(0)));
    if (random.next() * e.area >= first) b = corner(2), c = corner(3);
  }
  const double s = std::sqrt(random.next()), t = random.next();
  return (1 - s) * a + s * (1 - t) * b + s * t * c;
}

Lights::Sample Lights::sample(Random& random) const {
  const double pick = random.next();
  const std::size_t i =
      std::min(std::size_t(std::lower_bound(cumulative_.begin(), cumulative_.end(), pick) -
                           cumulative_.begin()),
               emitters_.size() - 1);
  const Element& e = mesh_.elements[emitters_[i].element];
  const double chosen = cumulative_[i] - (i > 0 ? cumulative_[i - 1] : 0);
  return {emitters_[i].element, point_on(e, random), chosen / e.area};
}

Rgb Lights::direct(const Vec3& x, const Vec3& normal, const Vec3& geometric, const RayScene& rays,
                   int shadow_rays, Random& random) const {
  // The emitters x sees in front of both planes, with their exact unoccluded F.
  struct Seen {
    const Emitter* emitter;
    double form_factor;
  };
  thread_local std::vector<Seen> seen;
  seen.clear();
  double total = 0;
  std::array<Vec3, 4> corners;
  for (const Emitter& em : emitters_) {
    const Element& e = mesh_.elements[em.element];
    if (glm::dot(e.normal, x - e.centroid) <= 0) continue;  // behind it: one-sided
    for (int k = 0; k < e.vertex_count; ++k)
      corners[std::size_t(k)] = mesh_.vertices[e.v[std::size_t(k)]].position;
    const double f = point_to_polygon(x, normal, {corners.data(), std::size_t(e.vertex_count)});
    if (!(f > 0)) continue;
    seen.push_back({&em, f});
    total += f * em.weight;
  }
  if (seen.empty()) return Rgb(0);

  const Vec3 from = x + geometric * epsilon_;
  auto visible = [&](const Emitter& em) {
    Vec3 d = point_on(mesh_.elements[em.element], random) - from;
    const double distance = glm::length(d);
    d /= distance;
    return glm::dot(d, geometric) > 0 && !rays.occluded({from, d}, distance - 2 * epsilon_);
  };
  const int n = std::max(1, shadow_rays);
  Rgb sum(0);
  if (seen.size() <= std::size_t(n)) {
    // Few emitters: each gets its own rays, so a fully visible one adds exactly E F.
    const int each = n / int(seen.size());
    for (const Seen& s : seen) {
      int hits = 0;
      for (int r = 0; r < each; ++r) hits += visible(*s.emitter);
      sum += s.emitter->emission * (s.form_factor * hits / each);
    }
    return sum;
  }
  // Many: n rays stratified over the emitters by contribution (systematic sampling); each
  // ray that arrives adds its emitter's E F divided by the chance it was chosen.
  const double step = total / n;
  double next = random.next() * step, reached = 0;
  for (const Seen& s : seen) {
    const double share = s.form_factor * s.emitter->weight;
    reached += share;
    for (; next < reached; next += step)
      if (visible(*s.emitter)) sum += s.emitter->emission * (s.form_factor * step / share);
  }
  return sum;
}

}  // namespace bumprad
