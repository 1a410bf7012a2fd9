#include "solver/radiosity/group_proxies.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "solver/scene/geometry.h"
#include "solver/util/parallel.h"

namespace bumprad {
namespace {

// A group of fewer elements is drawn as it is: its proxy would save little.
constexpr std::uint32_t kMinElements = 16;
// The levels' cells, in the surface's typical triangle sides (the median over its groups'
// elements). Each level is kept for a group only where it halves the triangles of the
// finer one kept (or of the group).
constexpr std::array<double, 3> kLevelSides{2, 4, 8};
constexpr double kMaxShare = 0.5;

// The side of a square of the element's area (of a right triangle's legs for a triangle).
double side(const Element& e) {
  return std::sqrt(e.vertex_count == 4 ? e.area : 2 * e.area);
}

// The distance from p to triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return glm::length(ap);
  const Vec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return glm::length(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
  const Vec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return glm::length(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  const double denom = 1 / (va + vb + vc);
  return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

// A cluster: the surface, the cell, which way the vertices' normals lean most (one of six),
// so that the two sides of a thin part, a cell apart, stay two, and whether they lie on the
// surface's outline, so that it stays where it is (the terrain's along the walls had moved
// half a cell in).
struct ClusterKey {
  std::uint32_t surface;
  std::int64_t x, y, z;
  int lean;
  bool outline;
  bool operator==(const ClusterKey&) const = default;
};
struct ClusterKeyHash {
  std::size_t operator()(const ClusterKey& k) const {
    std::uint64_t h = k.surface;
    for (std::uint64_t v : {std::uint64_t(k.x), std::uint64_t(k.y), std::uint64_t(k.z),
                            std::uint64_t(2 * k.lean + (k.outline ? 1 : 0))})
      h = (h ^ v) * 0x100000001b3ull + (h >> 29);
    return std::size_t(h);
  }
};

int lean(const Vec3& n) {
  const Vec3 a = glm::abs(n);
  const int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  return 2 * axis + (n[axis] < 0 ? 1 : 0);
}

// The sides of the elements of the surfaces that take proxies, each by its two vertices
// (the lower first), in runs of one such pair each.
struct Sides {
  struct Side {
    std::uint64_t key;
    std::uint32_t element;
    int corner;  // from corner `corner` to the next
  };
  std::vector<Side> sides;
  std::vector<std::size_t> runs;  // run k: sides[runs[k], runs[k + 1])

  Sides(const Mesh& mesh, const std::vector<bool>& surfaces) {
    for (std::uint32_t i = 0; i < mesh.elements.size(); ++i) {
      const Element& e = mesh.elements[i];
      if (!surfaces[e.surface]) continue;
      for (int k = 0; k < e.vertex_count; ++k) {
        const std::uint64_t a = e.v[std::size_t(k)], b = e.v[std::size_t((k + 1) % e.vertex_count)];
        sides.push_back({std::min(a, b) << 32 | std::max(a, b), i, k});
      }
    }
    std::sort(sides.begin(), sides.end(),
              [](const Side& a, const Side& b) { return a.key < b.key; });
    for (std::size_t i = 0; i < sides.size(); ++i)
      if (i == 0 || sides[i].key != sides[i - 1].key) runs.push_back(i);
    runs.push_back(sides.size());
  }
};

// What every level shares: which groups take proxies, their surfaces' triangle sides, the
// elements' sides and the vertices on their surface's outline (on a side one element has).
struct Setting {
  const Mesh& mesh;
  std::vector<bool> takes;          // per group
  std::vector<double> median_side;  // per surface; 0: it takes none
  Sides sides;
  std::vector<bool> outline;  // per vertex
};

// The vertices' clusters at one cell size, and each one's representative.
struct Clusters {
  std::vector<std::int32_t> of;  // per vertex; -1: in no group that takes proxies
  std::vector<Vec3> point;
};

Clusters cluster(const Setting& s, double cell_sides) {
  const Mesh& mesh = s.mesh;
  Clusters out{std::vector<std::int32_t>(mesh.vertices.size(), -1), {}};
  std::unordered_map<ClusterKey, std::int32_t, ClusterKeyHash> keys;
  std::vector<double> members;
  for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
    if (!s.takes[g]) continue;
    for (std::uint32_t i = mesh.groups[g].first; i < mesh.groups[g].first + mesh.groups[g].count;
         ++i) {
      const Element& e = mesh.elements[i];
      const double cell = std::max(cell_sides * s.median_side[e.surface], 1e-6 * mesh.diagonal());
      for (int k = 0; k < e.vertex_count; ++k) {
        const std::uint32_t v = e.v[std::size_t(k)];
        if (out.of[v] >= 0) continue;
        const Vertex& vertex = mesh.vertices[v];
        const glm::dvec3 at = glm::floor((vertex.position - mesh.bounds_min) / cell);
        const ClusterKey key{e.surface,          std::int64_t(at.x),  std::int64_t(at.y),
                             std::int64_t(at.z), lean(vertex.normal), s.outline[v]};
        const auto [it, added] = keys.try_emplace(key, std::int32_t(out.point.size()));
        if (added) out.point.emplace_back(0), members.push_back(0);
        out.of[v] = it->second;
        out.point[std::size_t(it->second)] += vertex.position;
        members[std::size_t(it->second)] += 1;
      }
    }
  }
  // The mean of points on a curved surface lies inside it (a ball's proxies filled 2.3 %
  // less of a hemi-cube than the ball): each representative moves along its vertices' mean
  // normal to where it lies best on their tangent planes (least squares).
  for (std::size_t c = 0; c < out.point.size(); ++c) out.point[c] /= members[c];
  std::vector<Vec3> normal(out.point.size(), Vec3(0));
  for (std::size_t v = 0; v < out.of.size(); ++v)
    if (out.of[v] >= 0) normal[std::size_t(out.of[v])] += mesh.vertices[v].normal;
  for (Vec3& n : normal)
    if (glm::length(n) > 0) n = glm::normalize(n);
  std::vector<double> moved(out.point.size(), 0), weight(out.point.size(), 0);
  for (std::size_t v = 0; v < out.of.size(); ++v) {
    if (out.of[v] < 0) continue;
    const std::size_t c = std::size_t(out.of[v]);
    const Vec3& n = mesh.vertices[v].normal;
    const double along = glm::dot(n, normal[c]);
    moved[c] += along * glm::dot(n, mesh.vertices[v].position - out.point[c]);
    weight[c] += along * along;
  }
  for (std::size_t c = 0; c < out.point.size(); ++c)
    if (weight[c] > 0) out.point[c] += normal[c] * (moved[c] / weight[c]);
  return out;
}

// One level: each group's triangles whose corners fall in three clusters (once each), its
// skirts and its error. `budget` (per group) is the most triangles its proxy may have; a
// kept proxy lowers it for the next level.
ProxyLevel level(const Setting& s, double cell_sides, std::vector<double>& budget,
                 std::stop_token stop) {
  const Mesh& mesh = s.mesh;
  const Clusters clusters = cluster(s, cell_sides);
  auto point = [&](std::uint32_t vertex) {
    return clusters.point[std::size_t(clusters.of[vertex])];
  };
  ProxyLevel out;
  out.groups.resize(mesh.groups.size());
  struct Candidate {
    std::array<std::int32_t, 3> clusters;  // in its source's order
    std::array<std::int32_t, 3> sorted;
    std::uint32_t element;
  };
  std::vector<Candidate> candidates;
  std::vector<std::array<std::int32_t, 3>> triangle_clusters;  // per proxy triangle
  for (std::size_t g = 0; g < mesh.groups.size() && !stop.stop_requested(); ++g) {
    if (!s.takes[g]) continue;
    const ElementGroup& group = mesh.groups[g];
    candidates.clear();
    for (std::uint32_t i = group.first; i < group.first + group.count; ++i) {
      const Element& e = mesh.elements[i];
      for (int t = 0; t + 2 < e.vertex_count; ++t) {  // (v0, v1, v2), then a quad's (v0, v2, v3)
        const std::array<std::int32_t, 3> c{clusters.of[e.v[0]],
                                            clusters.of[e.v[std::size_t(t + 1)]],
                                            clusters.of[e.v[std::size_t(t + 2)]]};
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
        std::array<std::int32_t, 3> sorted = c;
        std::sort(sorted.begin(), sorted.end());
        candidates.push_back({c, sorted, i});
      }
    }
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const Candidate& a, const Candidate& b) { return a.sorted < b.sorted; });
    candidates.erase(
        std::unique(candidates.begin(), candidates.end(),
                    [](const Candidate& a, const Candidate& b) { return a.sorted == b.sorted; }),
        candidates.end());
    if (candidates.empty() || double(candidates.size()) > budget[g]) continue;
    ProxyLevel::Group& proxy = out.groups[g];
    proxy.first = std::uint32_t(out.triangles.size());
    for (const Candidate& c : candidates) {
      const Vec3 &a = clusters.point[std::size_t(c.clusters[0])],
                 &b = clusters.point[std::size_t(c.clusters[1])],
                 &d = clusters.point[std::size_t(c.clusters[2])];
      const Vec3 n = glm::cross(b - a, d - a);
      if (!(glm::length(n) > 0)) continue;
      triangle_clusters.push_back(c.clusters);
      out.triangles.push_back({{glm::vec3(a), glm::vec3(b), glm::vec3(d)},
                               glm::vec3((a + b + d) / 3.0),
                               glm::vec3(glm::normalize(n)),
                               c.element});
    }
    proxy.count = std::uint32_t(out.triangles.size()) - proxy.first;
    if (proxy.count > 0) budget[g] = kMaxShare * proxy.count;
  }

  // Skirts: where a group with a proxy meets another group, the strip between its side and
  // the side's image on the proxy. Without them a crack between a proxy and its neighbour
  // drawn as it is let shots see through a closed room's floor: 0.5 % of the terrain's light
  // escaped. Drawn by group, as the triangles are.
  std::vector<std::array<std::uint32_t, 2>> skirt_of;  // per skirt: its group, the other
  std::vector<ProxyTriangle> skirts;
  const Sides& sides = s.sides;
  for (std::size_t k = 0; k + 1 < sides.runs.size(); ++k) {
    if (sides.runs[k + 1] - sides.runs[k] != 2) continue;  // an outline, or a fin of three
    for (std::size_t own = 0; own < 2; ++own) {
      const Sides::Side& side = sides.sides[sides.runs[k] + own];
      const Element& e = mesh.elements[side.element];
      const std::uint32_t other = mesh.elements[sides.sides[sides.runs[k] + 1 - own].element].group;
      if (out.groups[e.group].count == 0 || other == e.group) continue;
      const std::uint32_t a = e.v[std::size_t(side.corner)],
                          b = e.v[std::size_t((side.corner + 1) % e.vertex_count)];
      auto add = [&](const Vec3& x, const Vec3& y, const Vec3& z) {
        if (!(glm::length(glm::cross(y - x, z - x)) > 0)) return;
        skirts.push_back({{glm::vec3(x), glm::vec3(y), glm::vec3(z)},
                          glm::vec3((x + y + z) / 3.0),
                          glm::vec3(e.normal),
                          side.element});
        skirt_of.push_back({e.group, other});
      };
      const Vec3 &pa = mesh.vertices[a].position, &pb = mesh.vertices[b].position;
      add(pa, pb, point(b));
      if (clusters.of[a] != clusters.of[b]) add(pa, point(b), point(a));
    }
  }
  std::vector<std::uint32_t> order(skirts.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
    return skirt_of[x][0] < skirt_of[y][0];
  });
  for (std::uint32_t i : order) {
    ProxyLevel::Group& proxy = out.groups[skirt_of[i][0]];
    if (proxy.skirt_count++ == 0) proxy.skirt_first = std::uint32_t(out.skirts.size());
    out.skirts.push_back(skirts[i]);
    out.skirt_neighbour.push_back(skirt_of[i][1]);
  }

  // Each group's error, both ways: the farthest of its vertices from the proxies' surface,
  // as near as the fans of proxy triangles about its own and its neighbours' points (of any
  // group: a vertex on a group's edge may lie nearest its neighbour's) find it; and the
  // farthest of its proxy's corners from the triangles of its cluster's vertices. A vertex
  // may be a cluster of its own with no triangle (its surface collapsed onto its
  // neighbours'), and its own fan then empty; with none near at all it is never coarse.
  std::vector<std::vector<std::uint32_t>> fan(clusters.point.size());
  for (std::uint32_t t = 0; t < out.triangles.size(); ++t)
    for (std::int32_t c : triangle_clusters[t]) fan[std::size_t(c)].push_back(t);
  auto from_fan = [&](const Vec3& p, std::size_t c) {
    double d = INFINITY;
    for (std::uint32_t t : fan[c]) {
      const ProxyTriangle& triangle = out.triangles[t];
      d = std::min(d, distance_to_triangle(p, Vec3(triangle.corners[0]), Vec3(triangle.corners[1]),
                                           Vec3(triangle.corners[2])));
    }
    return d;
  };
  std::vector<double> nearest(mesh.vertices.size(), INFINITY);
  parallel_for(
      int(mesh.vertices.size()),
      [&](int v) {
        if (clusters.of[std::size_t(v)] >= 0)
          nearest[std::size_t(v)] = from_fan(mesh.vertices[std::size_t(v)].position,
                                             std::size_t(clusters.of[std::size_t(v)]));
      },
      stop);
  // Its neighbours' fans only for a vertex its own leaves over a quarter of a cell off (1-2 %
  // of them on the scale bench's figures; all of them had taken 6 s at 1M triangles).
  std::vector<double> off(clusters.point.size(), INFINITY);  // a point from its triangles
  for (std::size_t g = 0; g < mesh.groups.size() && !stop.stop_requested(); ++g) {
    if (!s.takes[g]) continue;
    const ElementGroup& group = mesh.groups[g];
    for (std::uint32_t i = group.first; i < group.first + group.count; ++i) {
      const Element& e = mesh.elements[i];
      const double close = 0.25 * cell_sides * s.median_side[e.surface];
      std::array<Vec3, 4> storage;
      const std::span<const Vec3> corner = element_corners(mesh, e, storage);
      for (int k = 0; k < e.vertex_count; ++k) {
        const std::uint32_t v = e.v[std::size_t(k)];
        const std::size_t c = std::size_t(clusters.of[v]);
        for (int t = 0; t + 2 < e.vertex_count; ++t)
          off[c] = std::min(
              off[c], distance_to_triangle(clusters.point[c], corner[0], corner[std::size_t(t + 1)],
                                           corner[std::size_t(t + 2)]));
        if (out.groups[g].count == 0 || nearest[v] <= close) continue;
        for (int j = 0; j < e.vertex_count; ++j)
          if (clusters.of[e.v[std::size_t(j)]] != std::int32_t(c))
            nearest[v] = std::min(
                nearest[v],
                from_fan(corner[std::size_t(k)], std::size_t(clusters.of[e.v[std::size_t(j)]])));
      }
    }
  }
  for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
    ProxyLevel::Group& proxy = out.groups[g];
    if (proxy.count == 0) continue;
    const ElementGroup& group = mesh.groups[g];
    for (std::uint32_t i = group.first; i < group.first + group.count; ++i)
      for (int k = 0; k < mesh.elements[i].vertex_count; ++k)
        proxy.error = std::max(proxy.error, nearest[mesh.elements[i].v[std::size_t(k)]]);
    for (std::uint32_t t = proxy.first; t < proxy.first + proxy.count; ++t)
      for (std::int32_t c : triangle_clusters[t])
        proxy.error = std::max(proxy.error, off[std::size_t(c)]);
  }
  return out;
}

}  // namespace

GroupProxies group_proxies(const Mesh& mesh, const std::vector<bool>& eligible,
                           std::stop_token stop) {
  GroupProxies out;
  out.spheres.resize(mesh.groups.size());
  if (eligible.size() != mesh.groups.size()) return out;
  std::vector<bool> takes(mesh.groups.size());
  for (std::size_t g = 0; g < takes.size(); ++g)
    takes[g] = eligible[g] && mesh.groups[g].count >= kMinElements;

  std::vector<std::vector<double>> sides(mesh.surface_count);
  for (std::size_t g = 0; g < mesh.groups.size(); ++g)
    if (takes[g])
      for (std::uint32_t i = mesh.groups[g].first; i < mesh.groups[g].first + mesh.groups[g].count;
           ++i)
        sides[mesh.elements[i].surface].push_back(side(mesh.elements[i]));
  std::vector<double> median(mesh.surface_count, 0);
  std::vector<bool> surfaces(mesh.surface_count, false);
  for (std::size_t s = 0; s < sides.size(); ++s) {
    if (sides[s].empty()) continue;
    auto middle = sides[s].begin() + long(sides[s].size() / 2);
    std::nth_element(sides[s].begin(), middle, sides[s].end());
    median[s] = *middle;
    surfaces[s] = true;
  }
  Setting setting{mesh, std::move(takes), std::move(median), Sides(mesh, surfaces),
                  std::vector<bool>(mesh.vertices.size(), false)};
  const Sides& all = setting.sides;
  for (std::size_t k = 0; k + 1 < all.runs.size(); ++k)
    if (all.runs[k + 1] - all.runs[k] == 1) {
      const std::uint64_t key = all.sides[all.runs[k]].key;
      setting.outline[key >> 32] = setting.outline[key & 0xffffffffu] = true;
    }

  std::vector<double> budget(mesh.groups.size());
  for (std::size_t g = 0; g < budget.size(); ++g) {
    double triangles = 0;
    for (std::uint32_t i = mesh.groups[g].first; i < mesh.groups[g].first + mesh.groups[g].count;
         ++i)
      triangles += mesh.elements[i].vertex_count - 2;
    budget[g] = kMaxShare * triangles;
  }
  for (double cell_sides : kLevelSides) {
    out.levels.push_back(level(setting, cell_sides, budget, stop));
    if (stop.stop_requested()) return {{}, std::vector<GroupProxies::Sphere>(mesh.groups.size())};
  }

  for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
    GroupProxies::Sphere& sphere = out.spheres[g];
    const ElementGroup& group = mesh.groups[g];
    sphere.centre = group.centroid;
    sphere.radius = run_radius(mesh, group);
    for (const ProxyLevel& l : out.levels) {
      const ProxyLevel::Group& proxy = l.groups[g];
      for (std::uint32_t t = proxy.first; t < proxy.first + proxy.count; ++t)
        for (const glm::vec3& corner : l.triangles[t].corners)
          sphere.radius = std::max(sphere.radius, glm::length(Vec3(corner) - sphere.centre));
    }
  }
  return out;
}

}  // namespace bumprad
