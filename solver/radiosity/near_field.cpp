#include "solver/radiosity/near_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "solver/radiosity/form_factor_exact.h"
#include "solver/radiosity/vertex_radiosity.h"
#include "solver/scene/geometry.h"
#include "solver/util/parallel.h"

namespace bumprad {
namespace {

// The near set of a vertex reaches this many times the size of its largest element: far
// enough that the light from beyond changes about linearly across the vertex's elements (on
// the built-in scenes 2 and 3 times gave the same images as 1.5, with 1.8 and 4 times the
// terms).
constexpr double kReach = 1.5;
// A vertex whose near set fills nearly its whole view keeps its interpolated value: what it
// would hide is then a division by almost nothing.
constexpr double kMaxCovered = 0.9;

// Points standing for equal parts of an element: 4 x 4 of a quad, 3 x 3 of a triangle (half
// a quad's area) (part_points). The form factor to a nearby element changes fast across a
// receiver beside it; sixteen points average it to about 1 %.
std::vector<Vec3> area_points(const Mesh& mesh, const Element& e) {
  return part_points(mesh, e, e.vertex_count == 4 ? 4 : 3);
}

// A node of an element's corner terms (NearField::term_nodes) stands for all of them as
// one small patch, A cos cos / pi r^2 with their vector areas summed, at a shaded point
// that lies as many of its radii away as a single element must (kSmallPatchRadii), above the
// point's horizon, in front of the node (on the side its vector area faces), where its
// elements' normals lie within kNarrowCone of the node's. Exact where every element faces
// the point, but for the elements' spread about the centre (second order in radius over
// distance, as for one element); where the point sees some of them edge-on and beyond,
// their small negative parts are counted. On the scale bench's imported figures (a 0.4 m
// floor element beside a figure holds up to 10k of its triangles) the image is 0.01 % RMS
// (0.09 % at worst) from every term taken on its own, and the view pass's near field 2.2 x
// faster; a node taken only where every element faces the point was 1.1 x faster; 3 radii
// were 2.9 x faster but 0.03 % RMS and 1.4 % off Lambert's crease (near_field_test).
constexpr double kNodeRadii = kSmallPatchRadii;
constexpr double kNarrowCone = 1;  // radians
// Nodes of more terms are split in two (4 and 16 were slower than 8).
constexpr std::uint32_t kLeafTerms = 8;

// How many of a node's `count` terms its first child takes; none: it is a leaf. add_node()
// builds by it and tree_nodes() counts by it, so the two cannot part.
std::uint32_t first_half(std::uint32_t count) {
  return count > kLeafTerms ? count / 2 : 0;
}

// The node over terms[first, first + count), then its subtree's. The terms are reordered
// in place.
void add_node(const Mesh& mesh, std::span<NearField::CornerTerm> terms, std::uint32_t first,
              std::uint32_t count, std::span<NearField::TermNode> nodes, std::uint32_t& next) {
  const std::span<NearField::CornerTerm> own = terms.subspan(first, count);
  double area = 0;
  Vec3 centre(0), vector_area(0), lo(std::numeric_limits<double>::infinity()), hi(-lo),
      normal_lo(lo), normal_hi(hi);
  for (const NearField::CornerTerm& t : own) {
    const Element& e = mesh.elements[t.element];
    area += e.area;
    centre += e.area * e.centroid;
    vector_area += e.area * e.normal;
    lo = glm::min(lo, e.centroid);
    hi = glm::max(hi, e.centroid);
    normal_lo = glm::min(normal_lo, e.normal);
    normal_hi = glm::max(normal_hi, e.normal);
  }
  centre = area > 0 ? centre / area : (lo + hi) / 2.0;
  const double length = glm::length(vector_area);
  double radius = 0, cone_cos = length > 0 ? 1 : -1;  // of the widest normal off vector_area
  for (const NearField::CornerTerm& t : own) {
    const Element& e = mesh.elements[t.element];
    radius = std::max(radius, glm::length(e.centroid - centre) + double(t.radius));
    if (length > 0) cone_cos = std::min(cone_cos, glm::dot(e.normal, vector_area) / length);
  }
  cone_cos = std::clamp(cone_cos, -1.0, 1.0);
  const std::uint32_t self = next++;
  nodes[self] = {centre,
                 float(radius),
                 glm::vec3(vector_area),
                 float(cone_cos),
                 float(std::sqrt(1 - cone_cos * cone_cos)),
                 first,
                 count,
                 0,
                 own.front().corners};
  if (const std::uint32_t half = first_half(count)) {
    // Halves at the median along the widest axis: of their normals while those spread
    // wider than kNarrowCone (a thin part's two sides lie close together but face apart),
    // then of their centroids.
    const bool by_normal = cone_cos < std::cos(kNarrowCone);
    const Vec3 extent = by_normal ? normal_hi - normal_lo : hi - lo;
    const int axis =
        extent.x > extent.y ? (extent.x > extent.z ? 0 : 2) : (extent.y > extent.z ? 1 : 2);
    auto key = [&](const NearField::CornerTerm& t) {
      const Element& e = mesh.elements[t.element];
      return by_normal ? e.normal[axis] : e.centroid[axis];
    };
    std::nth_element(own.begin(), own.begin() + half, own.end(),
                     [&](const NearField::CornerTerm& a, const NearField::CornerTerm& b) {
                       return key(a) < key(b);
                     });
    add_node(mesh, terms, first, half, nodes, next);
    add_node(mesh, terms, first + half, count - half, nodes, next);
  }
  nodes[self].skip = next;
}

// The nodes add_node() makes over `count` terms.
std::uint32_t tree_nodes(std::uint32_t count) {
  const std::uint32_t half = first_half(count);
  return half ? 1 + tree_nodes(half) + tree_nodes(count - half) : 1;
}

// An element's corner terms ordered into trees, one for each set of corners, into `nodes`
// (as many as tree_nodes() counts over each set's terms).
void term_trees(const Mesh& mesh, std::span<NearField::CornerTerm> terms,
                std::span<NearField::TermNode> nodes) {
  std::stable_sort(terms.begin(), terms.end(),
                   [](const NearField::CornerTerm& a, const NearField::CornerTerm& b) {
                     return a.corners < b.corners;
                   });
  std::uint32_t next = 0;
  for (std::size_t first = 0; first < terms.size();) {
    std::size_t end = first + 1;
    while (end < terms.size() && terms[end].corners == terms[first].corners) ++end;
    add_node(mesh, terms, std::uint32_t(first), std::uint32_t(end - first), nodes, next);
    first = end;
  }
}

// Elements by the cells of a uniform grid their bounding boxes overlap.
class ElementGrid {
 public:
  ElementGrid(const Mesh& mesh, double cell) : mesh_(mesh), cell_(cell) {
    for (std::uint32_t i = 0; i < mesh.elements.size(); ++i) {
      const auto [lo, hi] = box(mesh.elements[i]);
      const std::uint32_t surface = mesh.elements[i].surface;
      for (long x = lo.x; x <= hi.x; ++x)
        for (long y = lo.y; y <= hi.y; ++y)
          for (long z = lo.z; z <= hi.z; ++z) {
            Cell& c = cells_[key(x, y, z)];
            c.only_surface = c.elements.empty() || c.only_surface == surface ? surface : kMixed;
            c.elements.push_back(i);
          }
    }
  }

  // The elements of surfaces other than `own` whose bounding boxes may come within `radius`
  // of `p`, once each. (Inside a fine surface, away from others, a vertex's cells hold its
  // own surface alone: the 100k room's floor vertices each sorted a hundred of its triangles
  // only to skip them.)
  void near(const Vec3& p, double radius, std::uint32_t own,
            std::vector<std::uint32_t>& out) const {
    out.clear();
    const glm::dvec3 lo = glm::floor((p - radius - mesh_.bounds_min) / cell_),
                     hi = glm::floor((p + radius - mesh_.bounds_min) / cell_);
    for (long x = long(lo.x); x <= long(hi.x); ++x)
      for (long y = long(lo.y); y <= long(hi.y); ++y)
        for (long z = long(lo.z); z <= long(hi.z); ++z)
          if (auto it = cells_.find(key(x, y, z));
              it != cells_.end() && it->second.only_surface != own)
            for (std::uint32_t i : it->second.elements)
              if (mesh_.elements[i].surface != own) out.push_back(i);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

 private:
  std::pair<glm::ivec3, glm::ivec3> box(const Element& e) const {
    Vec3 lo(mesh_.vertices[e.v[0]].position), hi(lo);
    for (int k = 1; k < e.vertex_count; ++k) {
      lo = glm::min(lo, mesh_.vertices[e.v[std::size_t(k)]].position);
      hi = glm::max(hi, mesh_.vertices[e.v[std::size_t(k)]].position);
    }
    return {glm::ivec3(glm::floor((lo - mesh_.bounds_min) / cell_)),
            glm::ivec3(glm::floor((hi - mesh_.bounds_min) / cell_))};
  }
  static std::uint64_t key(long x, long y, long z) {
    return (std::uint64_t(x & 0x1fffff) << 42) | (std::uint64_t(y & 0x1fffff) << 21) |
           std::uint64_t(z & 0x1fffff);
  }

  static constexpr std::uint32_t kMixed = std::numeric_limits<std::uint32_t>::max();
  struct Cell {
    std::vector<std::uint32_t> elements;
    std::uint32_t only_surface = kMixed;  // the surface of all its elements, or kMixed
  };

  const Mesh& mesh_;
  double cell_;
  std::unordered_map<std::uint64_t, Cell> cells_;
};

// Each vertex's elements, laid end to end.
class VertexElements {
 public:
  explicit VertexElements(const Mesh& mesh) : first_(mesh.vertices.size() + 1, 0) {
    for (const Element& e : mesh.elements)
      for (int k = 0; k < e.vertex_count; ++k) ++first_[e.v[std::size_t(k)] + 1];
    for (std::size_t v = 0; v + 1 < first_.size(); ++v) first_[v + 1] += first_[v];
    elements_.resize(first_.back());
    std::vector<std::uint32_t> fill(first_.begin(), first_.end() - 1);
    for (std::uint32_t i = 0; i < mesh.elements.size(); ++i)
      for (int k = 0; k < mesh.elements[i].vertex_count; ++k)
        elements_[fill[mesh.elements[i].v[std::size_t(k)]]++] = i;
  }
  std::span<const std::uint32_t> of(std::uint32_t v) const {
    return {elements_.data() + first_[v], elements_.data() + first_[v + 1]};
  }

 private:
  std::vector<std::uint32_t> first_, elements_;
};

}  // namespace

NearField::NearField(const Mesh& mesh, const RayScene& rays, std::span<const double> open,
                     std::stop_token stop)
    : mesh_(mesh), first_(mesh.vertices.size() + 1, 0), covered_(mesh.vertices.size(), 0.0) {
  const std::size_t vertex_count = mesh.vertices.size(), element_count = mesh.elements.size();
  if (element_count == 0) return;
  if (!open.empty()) {
    open_gain_.resize(element_count);
    for (std::size_t i = 0; i < element_count; ++i)
      open_gain_[i] = open[i] > 0 ? float(1 / open[i]) : 1.0f;
  }
  const VertexElements adjacent(mesh);
  std::vector<double> radius(element_count), sizes(element_count);
  for (std::size_t i = 0; i < element_count; ++i) {
    radius[i] = element_radius(mesh, mesh.elements[i]);
    sizes[i] = std::sqrt(mesh.elements[i].area);
  }
  std::nth_element(sizes.begin(), sizes.begin() + long(element_count / 2), sizes.end());
  const ElementGrid grid(mesh, std::max(kReach * sizes[element_count / 2], mesh.diagonal() / 256));

  // Near sets assume their elements visible, but a surface may hide another one close by (a
  // rug the floor under it): an element is left out unless a ray from the centroid of one of
  // the vertex's elements reaches its centroid.
  const double epsilon = ray_epsilon(mesh);
  auto seen_from = [&](std::span<const std::uint32_t> around, const Element& target) {
    const Vec3 to = target.centroid + target.normal * epsilon;
    for (std::uint32_t i : around) {
      const Vec3 from = mesh.elements[i].centroid + mesh.elements[i].normal * epsilon;
      const double distance = glm::length(to - from);
      if (distance > 0 && !rays.occluded({from, (to - from) / distance}, distance - epsilon))
        return true;
    }
    return false;
  };

  // Per vertex, on every core; then laid end to end.
  std::vector<std::vector<Term>> per_vertex(vertex_count);
  parallel_for(
      int(vertex_count),
      [&](int index) {
        const std::uint32_t v = std::uint32_t(index);
        const std::span<const std::uint32_t> around = adjacent.of(v);
        double size = 0, open_area = 0;
        for (std::uint32_t i : around) {
          size = std::max(size, std::sqrt(mesh.elements[i].area));
          open_area += mesh.elements[i].area * (open.empty() ? 1 : open[i]);
        }
        if (!(open_area > 0)) return;
        const Vec3& p = mesh.vertices[v].position;
        const std::uint32_t surface = mesh.elements[around.front()].surface;
        std::vector<std::uint32_t> candidates;
        grid.near(p, kReach * size, surface, candidates);
        // Most vertices (inside a surface, away from others) have no near set: their
        // elements' points are made for the first candidate.
        std::vector<std::vector<Vec3>> points;
        std::vector<Term>& terms = per_vertex[v];
        double covered = 0;
        for (std::uint32_t j : candidates) {
          const Element& ej = mesh.elements[j];
          if (glm::length(ej.centroid - p) - radius[j] > kReach * size || !seen_from(around, ej))
            continue;
          // Averaged as vertex_radiosity() averages: each element's whole area, over the open
          // area (a buried point lies behind the faces that bury it and sees none of them).
          if (points.empty())
            for (std::uint32_t i : around) points.push_back(area_points(mesh, mesh.elements[i]));
          double sum = 0;
          for (std::size_t a = 0; a < around.size(); ++a) {
            const Element& e = mesh.elements[around[a]];
            double mean = 0;
            for (const Vec3& q : points[a])
              mean += point_to_element(mesh, ej, radius[j], q, e.normal);
            sum += e.area * mean / double(points[a].size());
          }
          if (sum > 0) {
            terms.push_back({j, float(radius[j]), sum / open_area});
            covered += sum / open_area;
          }
        }
        if (covered > kMaxCovered) terms.clear();
        covered_[v] = terms.empty() ? 0 : covered;
      },
      stop);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    first_[v] = std::uint32_t(terms_.size());
    terms_.insert(terms_.end(), per_vertex[v].begin(), per_vertex[v].end());
  }
  first_[vertex_count] = std::uint32_t(terms_.size());

  // Merged once here, not at every shaded point (the merge had cost as much as the form
  // factors beside the scale bench's imported figures, whose elements' corners hold 179
  // terms on average at 134k triangles), then ordered into trees (term_nodes). Twice: first
  // counted, then written in place, so that no element's terms are held twice (the objects
  // family at 1M triangles: the copies had been a fifth of its peak memory).
  auto merge = [&](std::uint32_t element, auto&& take) {
    const Element& e = mesh.elements[element];
    std::array<std::span<const Term>, 4> lists;
    for (int k = 0; k < e.vertex_count; ++k) lists[std::size_t(k)] = terms(e.v[std::size_t(k)]);
    std::array<std::size_t, 4> next{};
    for (;;) {
      const Term* t = nullptr;
      for (std::size_t k = 0; k < std::size_t(e.vertex_count); ++k)
        if (next[k] < lists[k].size() && (!t || lists[k][next[k]].element < t->element))
          t = &lists[k][next[k]];
      if (!t) break;
      CornerTerm term{t->element, t->radius, 0};
      for (std::size_t k = 0; k < std::size_t(e.vertex_count); ++k)
        if (next[k] < lists[k].size() && lists[k][next[k]].element == term.element) {
          term.corners = std::uint8_t(term.corners | (1u << k));
          ++next[k];
        }
      take(term);
    }
  };
  corner_first_.assign(element_count + 1, 0);
  node_first_.assign(element_count + 1, 0);
  parallel_for(
      int(element_count),
      [&](int index) {
        std::array<std::uint32_t, 16> by_corners{};
        merge(std::uint32_t(index), [&](const CornerTerm& t) { ++by_corners[t.corners]; });
        std::uint32_t count = 0, nodes = 0;
        for (std::uint32_t n : by_corners)
          if (n > 0) count += n, nodes += tree_nodes(n);
        corner_first_[std::size_t(index) + 1] = count;
        node_first_[std::size_t(index) + 1] = nodes;
      },
      stop);
  for (std::size_t i = 0; i < element_count; ++i) {
    corner_first_[i + 1] += corner_first_[i];
    node_first_[i + 1] += node_first_[i];
  }
  corner_terms_.resize(corner_first_.back());
  nodes_.resize(node_first_.back());
  parallel_for(
      int(element_count),
      [&](int index) {
        const std::uint32_t element = std::uint32_t(index);
        CornerTerm* out = corner_terms_.data() + corner_first_[element];
        merge(element, [&](const CornerTerm& t) { *out++ = t; });
        term_trees(
            mesh,
            {corner_terms_.data() + corner_first_[element],
             corner_terms_.data() + corner_first_[element + 1]},
            {nodes_.data() + node_first_[element], nodes_.data() + node_first_[element + 1]});
      },
      stop);
  if (stop.stop_requested()) {  // some elements' terms unwritten: none kept
    corner_first_.assign(element_count + 1, 0);
    node_first_.assign(element_count + 1, 0);
    corner_terms_.clear();
    nodes_.clear();
  }
}

NearFieldShading::NearFieldShading(const NearField& near, std::span<const Rgb> reflected)
    : near_(near), reflected_(reflected), near_light_(near.mesh().vertices.size(), Rgb(0)) {
  for (std::uint32_t v = 0; v < near_light_.size(); ++v)
    for (const NearField::Term& t : near.terms(v))
      near_light_[v] += reflected[t.element] * (near.open_gain(t.element) * t.mean_form_factor);
  // Leaves from their terms, then each parent from its two children (its next node and
  // that one's skip), last node first.
  const Mesh& mesh = near.mesh();
  const std::uint32_t element_count = std::uint32_t(mesh.elements.size());
  node_light_.resize(element_count > 0 ? near.first_node(element_count) : 0);
  parallel_for(int(element_count), [&](int index) {
    const std::uint32_t element = std::uint32_t(index);
    const std::span<const NearField::TermNode> nodes = near.term_nodes(element);
    const std::span<const NearField::CornerTerm> terms = near.corner_terms(element);
    std::array<glm::vec3, 3>* light = node_light_.data() + near.first_node(element);
    for (std::size_t n = nodes.size(); n-- > 0;) {
      std::array<glm::vec3, 3>& sum = light[n];
      sum.fill(glm::vec3(0));
      if (nodes[n].skip == n + 1) {
        for (const NearField::CornerTerm& t : terms.subspan(nodes[n].first, nodes[n].count)) {
          const Element& e = mesh.elements[t.element];
          const Rgb l = reflected[t.element] * (near.open_gain(t.element) * e.area);
          for (int c = 0; c < 3; ++c) sum[std::size_t(c)] += glm::vec3(l[c] * e.normal);
        }
      } else {
        for (int c = 0; c < 3; ++c)
          sum[std::size_t(c)] =
              light[n + 1][std::size_t(c)] + light[nodes[n + 1].skip][std::size_t(c)];
      }
    }
  });
}

Rgb NearFieldShading::correction(const Element& element, const std::array<double, 4>& weights,
                                 const Vec3& point, const Vec3& normal, const Rgb& reflectance,
                                 std::span<const Rgb> vertex_values) const {
  // Per corner k: its value V = rho (H_env (1 - S) + N), the light H_env from beyond the
  // near set filling the part 1 - S of its view and the near set's own N (both averaged
  // over its elements). At the point the near set fills S(x) and gives N(x) exactly, so
  //   B(x) - V = rho (N(x) - N) - (V - rho N) (S(x) - S) / (1 - S).
  // Each of the corners' terms is taken once for all the corners that hold it
  // (NearField::corner_terms), and a node of them far from the point as one small patch
  // (term_nodes). (A cache of 64 form factors, searched term by term, had cost more than the
  // form factors beside the 100k room's floor, whose wall vertices hold 1,650 terms.)
  const int n = element.vertex_count;
  unsigned active = 0;
  for (int k = 0; k < n; ++k)
    if (weights[std::size_t(k)] != 0) active |= 1u << k;
  std::array<double, 4> covered{};
  std::array<Rgb, 4> light{Rgb(0), Rgb(0), Rgb(0), Rgb(0)};
  auto add = [&](unsigned corners, double f, const Rgb& l) {
    for (std::size_t k = 0; k < std::size_t(n); ++k)
      if (corners & (1u << k)) {
        covered[k] += f;
        light[k] += l;
      }
  };
  const Mesh& mesh = near_.mesh();
  const std::uint32_t index = std::uint32_t(&element - mesh.elements.data());
  const std::span<const NearField::CornerTerm> terms = near_.corner_terms(index);
  const std::span<const NearField::TermNode> nodes = near_.term_nodes(index);
  const std::array<glm::vec3, 3>* node_light = node_light_.data() + near_.first_node(index);
  const double narrow = std::cos(kNarrowCone);
  for (std::uint32_t i = 0; i < nodes.size();) {
    const NearField::TermNode& node = nodes[i];
    const unsigned corners = node.corners & active;
    if (!corners) {
      i = node.skip;
      continue;
    }
    const Vec3 d = node.centre - point;
    const double r2 = glm::dot(d, d), radius = node.radius, above = glm::dot(normal, d);
    if (above < -radius) {  // all below the point's horizon: none of their light
      i = node.skip;
      continue;
    }
    if (r2 > kNodeRadii * kNodeRadii * radius * radius) {
      const Vec3 out = -d, vector_area(node.vector_area);
      const double r = std::sqrt(r2), facing = glm::dot(vector_area, out);
      // Each element's normal lies within the cone's angle c of the node's, and the point
      // within b = asin(radius / r) of the node's direction from each: beyond 90 + c + b
      // degrees off, every element faces away.
      const double sin_b = radius / r, cos_b = std::sqrt(1 - sin_b * sin_b);
      if (node.cone_cos * cos_b - node.cone_sin * sin_b > 0 &&
          facing <
              -(node.cone_sin * cos_b + node.cone_cos * sin_b) * glm::length(vector_area) * r) {
        i = node.skip;
        continue;
      }
      if (facing > 0 && above > radius && node.cone_cos >= narrow) {
        const double scale = above / (std::numbers::pi * r2 * r2);
        const std::array<glm::vec3, 3>& l = node_light[i];
        add(corners, facing * scale,
            Rgb(glm::dot(Vec3(l[0]), out), glm::dot(Vec3(l[1]), out), glm::dot(Vec3(l[2]), out)) *
                scale);
        i = node.skip;
        continue;
      }
    }
    if (node.skip != i + 1) {  // its children
      ++i;
      continue;
    }
    for (const NearField::CornerTerm& t : terms.subspan(node.first, node.count)) {
      const double f = point_to_element(mesh, mesh.elements[t.element], t.radius, point, normal);
      add(corners, f, reflected_[t.element] * (near_.open_gain(t.element) * f));
    }
    i = node.skip;
  }
  Rgb change(0);
  for (std::size_t k = 0; k < std::size_t(n); ++k) {
    const std::uint32_t v = element.v[k];
    if (!(active & (1u << k)) || near_.terms(v).empty()) continue;
    const double s = near_.covered(v);
    const Rgb beyond = vertex_values[v] - reflectance * near_light_[v];
    change += weights[k] *
              (reflectance * (light[k] - near_light_[v]) - beyond * ((covered[k] - s) / (1 - s)));
  }
  return change;
}

}  // namespace bumprad
