#include "solver/scene/mesh.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <tuple>
#include <unordered_set>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/vector_relational.hpp>

#include "solver/scene/geometry.h"

namespace bumprad {
namespace {

// Every shape but the triangle mesh is a set of parametric grids P(u,v) on [0,1]^2.
struct Grid {
  std::function<Vec3(double, double)> position;
  int nu = 1, nv = 1;
};

std::array<Vec3, 8> box_corners(const BoxShape& box) {
  const glm::dmat4 r = rotated_about_axes(glm::dmat4(1.0), box.rotation_deg);
  std::array<Vec3, 8> c;
  for (int i = 0; i < 8; ++i) {
    Vec3 local((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5);
    c[i] = box.center + Vec3(r * glm::dvec4(local * box.size, 0.0));
  }
  return c;
}

// The six faces of a box as quads whose (p1-p0) x (p3-p0) points outward.
std::array<QuadShape, 6> box_faces(const BoxShape& box) {
  auto c = box_corners(box);
  auto at = [&](int x, int y, int z) { return c[x | (y << 1) | (z << 2)]; };
  return {{
      {{at(1, 0, 0), at(1, 1, 0), at(1, 1, 1), at(1, 0, 1)}},
      {{at(0, 0, 0), at(0, 0, 1), at(0, 1, 1), at(0, 1, 0)}},
      {{at(0, 1, 0), at(0, 1, 1), at(1, 1, 1), at(1, 1, 0)}},
      {{at(0, 0, 0), at(1, 0, 0), at(1, 0, 1), at(0, 0, 1)}},
      {{at(0, 0, 1), at(1, 0, 1), at(1, 1, 1), at(0, 1, 1)}},
      {{at(0, 0, 0), at(0, 1, 0), at(1, 1, 0), at(1, 0, 0)}},
  }};
}

int count_for(double length, double element_size, int minimum) {
  double n = std::ceil(length / element_size - 1e-9);
  n = std::clamp(n, double(minimum), double(Limits::kMaxGridCount));
  return int(n);
}

Grid quad_grid(const QuadShape& q, const MeshDensity& d, double size) {
  const auto& p = q.corners;
  Grid g;
  g.position = [p](double u, double v) {
    return (1 - u) * (1 - v) * p[0] + u * (1 - v) * p[1] + u * v * p[2] + (1 - u) * v * p[3];
  };
  g.nu = d.counts[0]
             ? d.counts[0]
             : count_for(std::max(glm::length(p[1] - p[0]), glm::length(p[2] - p[3])), size, 1);
  g.nv = d.counts[1]
             ? d.counts[1]
             : count_for(std::max(glm::length(p[3] - p[0]), glm::length(p[2] - p[1])), size, 1);
  return g;
}

// An orthonormal pair perpendicular to the unit vector `a`, with (e1, e2, a) right-handed.
void perpendicular_frame(const Vec3& a, Vec3& e1, Vec3& e2) {
  Vec3 helper = std::abs(a.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  e1 = glm::normalize(glm::cross(helper, a));
  e2 = glm::cross(a, e1);
}

std::vector<Grid> grids_for(const Object& object, double default_size) {
  const MeshDensity& d = object.density;
  double size = d.element_size > 0 ? d.element_size : default_size;
  std::vector<Grid> out;
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, QuadShape>) {
          out.push_back(quad_grid(s, d, size));
        } else if constexpr (std::is_same_v<T, BoxShape>) {
          for (const QuadShape& face : box_faces(s)) out.push_back(quad_grid(face, d, size));
        } else if constexpr (std::is_same_v<T, SphereShape>) {
          Grid g;
          Vec3 c = s.center;
          double r = s.radius;
          // phi runs clockwise seen from +y so that dP/du x dP/dv points outward.
          g.position = [c, r](double u, double v) {
            double phi = -2 * kPi * u, theta = kPi * (1 - v);
            return c + r * Vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                std::sin(theta) * std::sin(phi));
          };
          g.nu = d.counts[0] ? d.counts[0] : count_for(2 * kPi * r, size, 12);
          g.nv = d.counts[1] ? d.counts[1] : count_for(kPi * r, size, 6);
          out.push_back(g);
        } else if constexpr (std::is_same_v<T, CylinderShape>) {
          Vec3 axis = s.top - s.base;
          double h = glm::length(axis);
          Vec3 a = axis / h, e1, e2;
          perpendicular_frame(a, e1, e2);
          double r = s.radius;
          int around = d.counts[0] ? d.counts[0] : count_for(2 * kPi * r, size, 12);
          Grid side;
          side.position = [=, b = s.base](double u, double v) {
            double phi = 2 * kPi * u;
            return b + v * axis + r * (std::cos(phi) * e1 + std::sin(phi) * e2);
          };
          side.nu = around;
          side.nv = d.counts[1] ? d.counts[1] : count_for(h, size, 1);
          out.push_back(side);
          if (s.caps) {
            int radial = count_for(r, size, 1);
            Grid top, bottom;
            top.position = [=, t = s.top](double u, double v) {
              double phi = 2 * kPi * u;
              return t + v * r * (std::cos(phi) * e1 - std::sin(phi) * e2);
            };
            bottom.position = [=, b = s.base](double u, double v) {
              double phi = 2 * kPi * u;
              return b + v * r * (std::cos(phi) * e1 + std::sin(phi) * e2);
            };
            top.nu = bottom.nu = around;
            top.nv = bottom.nv = radial;
            out.push_back(top);
            out.push_back(bottom);
          }
        }
      },
      object.shape);
  return out;
}

int triangle_subdivisions(const TriangleMeshShape& m, const std::array<std::uint32_t, 3>& t,
                          const MeshDensity& d, double size) {
  if (d.counts[0]) return d.counts[0];
  double longest = 0;
  for (int e = 0; e < 3; ++e)
    longest = std::max(longest, glm::length(m.positions[t[(e + 1) % 3]] - m.positions[t[e]]));
  return count_for(longest, size, 1);
}

}  // namespace

namespace {

// Room for `more` in `v` at once, at least doubling: a 100k-triangle mesh grown vertex by
// vertex spent more time copying than placing them, and a reserve of exactly what is
// needed, surface after surface, would copy on every one.
template <typename T>
void reserve_more(std::vector<T>& v, std::size_t more) {
  if (v.size() + more > v.capacity()) v.reserve(std::max(v.size() + more, 2 * v.capacity()));
}

// What a triangle mesh's vertex brings to weld() beyond its position: a shading normal
// that must agree too (zero: none); the angle its triangle spans there, by which weld()
// averages the tangents it merges (zero: the first vertex's are kept); and whether its
// triangle's (u, v) run mirrored, which must agree too (MikkTSpace keeps mirrored UV
// islands' tangents apart where their seam's (u, v) coincide).
struct WeldInfo {
  Vec3 shading{0};
  double angle = 0;
  bool mirrored = false;
};

// Builds elements and patches for one surface at a time, welding vertices that coincide
// (sphere poles, cylinder seams, shared triangle-mesh edges) so that the surface is smooth.
class SurfaceBuilder {
 public:
  // After `stop`, every step returns at once and the mesh is left partial.
  SurfaceBuilder(Mesh& mesh, const Object& object, std::uint32_t object_index, double weld_tol,
                 std::stop_token stop)
      : mesh_(mesh),
        object_(object),
        object_index_(object_index),
        weld_tol_(weld_tol),
        stop_(std::move(stop)) {}

  bool stopped() const { return stop_.stop_requested(); }

  // `vertices`: about how many the surface will add, reserved at once.
  void begin_surface(std::size_t vertices = 0) {
    surface_ = mesh_.surface_count++;
    first_vertex_ = std::uint32_t(mesh_.vertices.size());
    corners_.clear();
    reserve_more(mesh_.vertices, vertices);
    corners_.reserve(vertices);
  }

  std::uint32_t add_vertex(const Vec3& p, glm::dvec2 uv, const Vec3& dpdu, const Vec3& dpdv,
                           const WeldInfo& corner = {}) {
    mesh_.vertices.push_back({p, Vec3(0), uv, dpdu, dpdv});
    corners_.push_back(corner);
    return std::uint32_t(mesh_.vertices.size() - 1);
  }

  // Merges coincident vertices added since begin_surface() (sorted by x, then y and z, and
  // swept along x); with `match_uv` or `match_shading`, only those whose (u, v) and
  // mirroring or shading normals agree too.
  void weld(bool match_uv = false, bool match_shading = false) {
    std::uint32_t n = std::uint32_t(mesh_.vertices.size()) - first_vertex_;
    remap_.resize(n);
    std::vector<std::uint32_t> order(n);
    for (std::uint32_t i = 0; i < n; ++i) order[i] = remap_[i] = first_vertex_ + i;
    auto& vs = mesh_.vertices;
    std::sort(order.begin(), order.end(), [&](auto a, auto b) {
      const Vec3 &p = vs[a].position, &q = vs[b].position;
      return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
    });
    // Where each run of vertices of one x ends. Within a run y only grows, so a vertex's
    // sweep leaves its run once y is past the tolerance: a grid's column (all of one x) had
    // been swept whole for each of its vertices.
    std::vector<std::uint32_t> run_end(n);
    for (std::uint32_t i = n; i-- > 0;)
      run_end[i] = i + 1 < n && vs[order[i + 1]].position.x == vs[order[i]].position.x
                       ? run_end[i + 1]
                       : i + 1;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (stopped()) return;
      std::uint32_t a = order[i];
      if (remap_[a - first_vertex_] != a) continue;
      for (std::uint32_t j = i + 1; j < n; ++j) {
        std::uint32_t b = order[j];
        if (vs[b].position.x - vs[a].position.x > weld_tol_) break;
        if (j < run_end[i] && vs[b].position.y - vs[a].position.y > weld_tol_) {
          j = run_end[i] - 1;
          continue;
        }
        if (glm::length(vs[b].position - vs[a].position) <= weld_tol_ &&
            remap_[b - first_vertex_] == b &&
            (!match_uv ||
             (glm::length(vs[b].uv - vs[a].uv) <= 1e-9 &&
              corners_[b - first_vertex_].mirrored == corners_[a - first_vertex_].mirrored)) &&
            (!match_shading || glm::length(corners_[b - first_vertex_].shading -
                                           corners_[a - first_vertex_].shading) <= 1e-3))
          remap_[b - first_vertex_] = a;
      }
    }
    average_tangents();
    // Only the vertices merged into are kept (a smooth triangle mesh adds three a triangle,
    // about six times what it shares): renumbered in order, remap_ pointing at the new ids.
    std::vector<std::uint32_t> renumbered(n);
    std::uint32_t kept = first_vertex_;
    for (std::uint32_t i = 0; i < n; ++i)
      if (remap_[i] == first_vertex_ + i) {
        vs[kept] = vs[first_vertex_ + i];
        renumbered[i] = kept++;
      }
    for (std::uint32_t i = 0; i < n; ++i) remap_[i] = renumbered[remap_[i] - first_vertex_];
    vs.resize(kept);
  }

  // A merged vertex's tangents as MikkTSpace builds them: the directions of its triangles'
  // tangents, each in the plane of the shading normal where there is one, weighted by the
  // angle each triangle spans there; their lengths likewise averaged (Blinn's perturbation
  // needs them). Independent of the triangles' order, and smooth across them.
  void average_tangents() {
    const std::uint32_t n = std::uint32_t(remap_.size());
    struct Sum {
      Vec3 du{0}, dv{0};
      double length_u = 0, length_v = 0, angle = 0;
    };
    std::vector<Sum> sums(n);
    auto direction = [](const Vec3& t, const Vec3& shading) {
      const Vec3 unit = glm::length(shading) > 0 ? glm::normalize(shading) : shading;
      const Vec3 in_plane = t - unit * glm::dot(unit, t);
      return glm::length(in_plane) > 0 ? glm::normalize(in_plane) : Vec3(0);
    };
    for (std::uint32_t i = 0; i < n; ++i) {
      const WeldInfo& c = corners_[i];
      if (!(c.angle > 0)) continue;
      const Vertex& v = mesh_.vertices[first_vertex_ + i];
      Sum& s = sums[remap_[i] - first_vertex_];
      s.du += c.angle * direction(v.dpdu, c.shading);
      s.dv += c.angle * direction(v.dpdv, c.shading);
      s.length_u += c.angle * glm::length(v.dpdu);
      s.length_v += c.angle * glm::length(v.dpdv);
      s.angle += c.angle;
    }
    for (std::uint32_t i = 0; i < n; ++i) {
      const Sum& s = sums[i];
      Vertex& v = mesh_.vertices[first_vertex_ + i];
      if (!(s.angle > 0) || !(glm::length(s.du) > 0) || !(glm::length(s.dv) > 0)) continue;
      v.dpdu = glm::normalize(s.du) * (s.length_u / s.angle);
      v.dpdv = glm::normalize(s.dv) * (s.length_v / s.angle);
    }
  }

  std::uint32_t patch_for(std::uint64_t key) {
    auto [it, inserted] = patch_keys_.try_emplace(key, std::uint32_t(pending_.size()));
    if (inserted) pending_.emplace_back();
    return it->second;
  }

  // Queues an element for patch `local_patch` and the group `group` names within it (none:
  // a group of its own); corners are vertex ids from add_vertex (remapped by weld()).
  // Degenerate corners collapse to a triangle or the element is dropped.
  void add_element(std::uint32_t local_patch, std::array<std::uint32_t, 4> v, int n,
                   std::optional<std::uint64_t> group = std::nullopt) {
    std::array<std::uint32_t, 4> w{};
    int m = 0;
    for (int i = 0; i < n; ++i) {
      std::uint32_t id = remap_.empty() ? v[i] : remap_[v[i] - first_vertex_];
      if (m > 0 && w[m - 1] == id) continue;
      w[m++] = id;
    }
    if (m > 1 && w[m - 1] == w[0]) --m;
    if (m < 3) return;
    Element e;
    e.v = w;
    e.vertex_count = m;
    e.surface = surface_;
    e.object = object_index_;
    e.material = object_.material;
    if (object_.flip_normals) std::reverse(e.v.begin(), e.v.begin() + m);
    if (!compute_element_geometry(mesh_.vertices, e)) return;
    // Keys of groups of their own lie above every cell key (cluster_key's top bit is clear).
    pending_[local_patch].push_back({group ? *group : (std::uint64_t(1) << 63) | own_groups_++, e});
  }

  // Moves the queued elements into the mesh patch by patch, each patch's groups in turn, so
  // that both are contiguous; patches may span surfaces (a faceted mesh's triangles).
  void flush() {
    std::size_t pending = 0;
    for (const auto& elems : pending_) pending += elems.size();
    reserve_more(mesh_.elements, pending);
    for (auto& elems : pending_) {
      if (stopped()) break;
      if (elems.empty()) continue;
      std::stable_sort(elems.begin(), elems.end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
      const std::uint32_t first = std::uint32_t(mesh_.elements.size());
      for (std::size_t i = 0; i < elems.size(); ++i) {
        if (i == 0 || elems[i].first != elems[i - 1].first) {
          if (i > 0) close_run(mesh_.groups);
          mesh_.groups.push_back({std::uint32_t(mesh_.elements.size()), 0});
        }
        Element& e = elems[i].second;
        e.patch = std::uint32_t(mesh_.patches.size());
        e.group = std::uint32_t(mesh_.groups.size() - 1);
        mesh_.elements.push_back(e);
      }
      close_run(mesh_.groups);
      mesh_.patches.push_back({first, 0});
      close_run(mesh_.patches);
    }
    pending_.clear();
    patch_keys_.clear();
    remap_.clear();
  }

 private:
  // The last run's count, area, centroid and normal, from the elements added since it began.
  void close_run(std::vector<ElementRun>& runs) {
    ElementRun& r = runs.back();
    r.count = std::uint32_t(mesh_.elements.size()) - r.first;
    r = element_run(mesh_.elements, r.first, r.count);
  }

  Mesh& mesh_;
  const Object& object_;
  std::uint32_t object_index_;
  double weld_tol_;
  std::stop_token stop_;
  std::uint32_t surface_ = 0;
  std::uint32_t first_vertex_ = 0;
  std::uint64_t own_groups_ = 0;
  std::vector<std::uint32_t> remap_;
  std::vector<WeldInfo> corners_;  // per vertex since begin_surface(), for weld()
  std::map<std::uint64_t, std::uint32_t> patch_keys_;
  std::vector<std::vector<std::pair<std::uint64_t, Element>>> pending_;  // group key, element
};

std::uint64_t patch_key(int pu, int pv) {
  return (std::uint64_t(pu) << 32) | std::uint32_t(pv);
}

void mesh_grid(SurfaceBuilder& sb, const Grid& g, int k) {
  sb.begin_surface();
  const double h = 1e-5;
  std::vector<std::uint32_t> ids;
  ids.reserve(std::size_t(g.nu + 1) * std::size_t(g.nv + 1));
  for (int j = 0; j <= g.nv; ++j) {
    if (sb.stopped()) return;
    for (int i = 0; i <= g.nu; ++i) {
      double u = double(i) / g.nu, v = double(j) / g.nv;
      double u0 = std::max(0.0, u - h), u1 = std::min(1.0, u + h);
      double v0 = std::max(0.0, v - h), v1 = std::min(1.0, v + h);
      Vec3 dpdu = (g.position(u1, v) - g.position(u0, v)) / (u1 - u0);
      Vec3 dpdv = (g.position(u, v1) - g.position(u, v0)) / (v1 - v0);
      ids.push_back(sb.add_vertex(g.position(u, v), {u, v}, dpdu, dpdv));
    }
  }
  sb.weld();
  auto at = [&](int i, int j) { return ids[std::size_t(j) * std::size_t(g.nu + 1) + i]; };
  for (int pv = 0; pv * k < g.nv; ++pv) {
    if (sb.stopped()) return;
    for (int pu = 0; pu * k < g.nu; ++pu) {
      std::uint32_t patch = sb.patch_for(patch_key(pu, pv));
      for (int j = pv * k; j < std::min(g.nv, (pv + 1) * k); ++j)
        for (int i = pu * k; i < std::min(g.nu, (pu + 1) * k); ++i)
          sb.add_element(patch, {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)}, 4);
    }
  }
  sb.flush();
}

// A triangle's (u, v) as an affine map of its barycentric coordinates, and the tangents
// dp/du, dp/dv that go with it. With the mesh's own uvs the tangents follow them (the
// convention of MikkTSpace per triangle: dp/du along increasing u); where those uvs are
// degenerate on a triangle, or there are none, the triangle's own parameterisation.
// `mirrored`: the (u, v) turn clockwise where the triangle's corners turn counter-clockwise.
struct TriangleUv {
  glm::dvec2 origin, along_b, along_c;
  Vec3 dpdu, dpdv;
  bool mirrored = false;
};
TriangleUv triangle_uv(const TriangleMeshShape& m, const std::array<std::uint32_t, 3>& t) {
  const Vec3 e1 = m.positions[t[1]] - m.positions[t[0]], e2 = m.positions[t[2]] - m.positions[t[0]];
  TriangleUv own{{0, 0}, {1, 0}, {0, 1}, e1, e2};
  if (m.uvs.empty()) return own;
  const glm::dvec2 u0 = m.uvs[t[0]], d1 = m.uvs[t[1]] - u0, d2 = m.uvs[t[2]] - u0;
  const double det = d1.x * d2.y - d1.y * d2.x;
  const double scale = std::max(glm::dot(d1, d1), glm::dot(d2, d2));
  if (!(std::abs(det) > 1e-12 * scale)) return {u0, d1, d2, e1, e2};
  // [e1 e2] = [dpdu dpdv] [d1 d2]: invert the 2 x 2 uv matrix.
  return {u0, d1, d2, (e1 * d2.y - e2 * d1.y) / det, (e2 * d1.x - e1 * d2.x) / det, det < 0};
}

// The angles of triangle (a, b, c) at its corners.
std::array<double, 3> corner_angles(const Vec3& a, const Vec3& b, const Vec3& c) {
  auto at = [](const Vec3& p, const Vec3& q, const Vec3& r) {
    const Vec3 x = q - p, y = r - p;
    return std::atan2(glm::length(glm::cross(x, y)), glm::dot(x, y));
  };
  return {at(a, b, c), at(b, c, a), at(c, a, b)};
}

// Tangents at a point of a triangle with the model's own tangent there (glTF's TANGENT:
// xyz along increasing u, w the handedness, up the texture along w n x t): dp/du along t
// and dp/dv, down the texture, along -w n x t, both in the plane of the normal n, each
// as long as the triangle's (u, v) make it.
std::pair<Vec3, Vec3> own_tangents(const TriangleUv& map, const Vec3& n, const glm::dvec4& t) {
  const Vec3 along = Vec3(t) - n * glm::dot(n, Vec3(t));
  if (!(glm::length(along) > 0)) return {map.dpdu, map.dpdv};
  const Vec3 u = glm::normalize(along);
  return {u * glm::length(map.dpdu),
          -(t.w < 0 ? -1.0 : 1.0) * glm::cross(n, u) * glm::length(map.dpdv)};
}

// The patch (or group) of a triangle mesh's element: elements share one when their
// centroids fall in one cube of side `cell` and their triangles face within one of the six
// axis directions, so a finely tessellated surface shoots from clusters of neighbouring
// triangles' elements, never from one patch per triangle, and a crease (a box's edge) still
// parts its faces' patches. 20 bits of each cell coordinate: a patch would join far cells
// only in a scene over 2^20 cells (10^6 patch sizes) across.
std::uint64_t cluster_key(const Vec3& centroid, const Vec3& facing, double cell) {
  int axis = 0;
  for (int c = 1; c < 3; ++c)
    if (std::abs(facing[c]) > std::abs(facing[axis])) axis = c;
  const std::uint64_t direction = std::uint64_t(2 * axis + (facing[axis] < 0));
  std::uint64_t key = direction << 60;
  for (int c = 0; c < 3; ++c)
    key |= (std::uint64_t(std::int64_t(std::floor(centroid[c] / cell))) & 0xFFFFF) << (40 - 20 * c);
  return key;
}

// The triangles of `m` by the plane they lie in (normal to 1e-4, offset to 1e-3 of the
// element size, so that a face cut into many triangles from single-precision data is one),
// in the order each plane first appears. Degenerate ones stand alone.
std::vector<std::vector<std::size_t>> coplanar_sets(const TriangleMeshShape& m, double size) {
  std::map<std::array<std::int64_t, 4>, std::size_t> index;
  std::vector<std::vector<std::size_t>> sets;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    const Vec3 a = m.positions[tri[0]];
    const Vec3 cross = glm::cross(m.positions[tri[1]] - a, m.positions[tri[2]] - a);
    const double length = glm::length(cross);
    if (!(length > 0)) {
      sets.push_back({t});
      continue;
    }
    const Vec3 n = cross / length;
    const std::array<std::int64_t, 4> key = {std::llround(n.x * 1e4), std::llround(n.y * 1e4),
                                             std::llround(n.z * 1e4),
                                             std::llround(glm::dot(n, a) / (size * 1e-3))};
    const auto [it, inserted] = index.try_emplace(key, sets.size());
    if (inserted) sets.emplace_back();
    sets[it->second].push_back(t);
  }
  return sets;
}

// Each input triangle is split into n^2 triangles on a barycentric grid (i, j); row j holds
// n + 1 - j vertices. Patches group neighbouring elements across triangles (cluster_key, in
// cubes of k element sizes), on faceted meshes too. A triangle at most one element size
// long is one element, and such triangles join groups (cubes of one element size): the
// light a shot sends is resolved per group, not per triangle finer than the scene needs.
void mesh_triangles(SurfaceBuilder& sb, const TriangleMeshShape& m, const MeshDensity& d,
                    double size, int k) {
  struct TriangleGrid {
    int n;
    std::uint32_t first_vertex;
  };
  auto emit = [&](std::size_t t, const TriangleGrid& g) {
    auto id = [&](int i, int j) {
      return g.first_vertex + std::uint32_t(j * (g.n + 1) - j * (j - 1) / 2 + i);
    };
    const auto& tri = m.triangles[t];
    const Vec3 a = m.positions[tri[0]], ab = m.positions[tri[1]] - a, ac = m.positions[tri[2]] - a;
    const Vec3 facing = glm::cross(ab, ac);
    for (int j = 0; j < g.n; ++j)
      for (int i = 0; i + j < g.n; ++i) {
        const Vec3 centroid = a + ((i + 1.0 / 3) / g.n) * ab + ((j + 1.0 / 3) / g.n) * ac;
        const std::uint32_t patch = sb.patch_for(cluster_key(centroid, facing, k * size));
        std::optional<std::uint64_t> group;
        if (g.n == 1) group = cluster_key(centroid, facing, size);
        sb.add_element(patch, {id(i, j), id(i + 1, j), id(i, j + 1), 0}, 3, group);
        if (i + j + 1 < g.n)
          sb.add_element(patch, {id(i + 1, j), id(i + 1, j + 1), id(i, j + 1), 0}, 3);
      }
  };
  // Each grid vertex carries the angle its triangle spans there: a corner's own, pi along an
  // edge, 2 pi inside (where nothing welds to it).
  auto add_grid = [&](const std::array<std::uint32_t, 3>& t) {
    Vec3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
    const TriangleUv map = triangle_uv(m, t);
    const std::array<double, 3> angles = corner_angles(a, b, c);
    const Vec3 facing = glm::normalize(glm::cross(b - a, c - a));
    TriangleGrid g{triangle_subdivisions(m, t, d, size), 0};
    for (int j = 0; j <= g.n; ++j)
      for (int i = 0; i + j <= g.n; ++i) {
        double u = double(i) / g.n, v = double(j) / g.n;
        auto at = [&](const auto& values) {
          return (1 - u - v) * values[t[0]] + u * values[t[1]] + v * values[t[2]];
        };
        WeldInfo corner;
        if (!m.normals.empty()) corner.shading = at(m.normals);
        corner.angle = i + j == 0                   ? angles[0]
                       : i == g.n                   ? angles[1]
                       : j == g.n                   ? angles[2]
                       : i * j == 0 || i + j == g.n ? std::numbers::pi
                                                    : 2 * std::numbers::pi;
        corner.mirrored = map.mirrored;
        Vec3 dpdu = map.dpdu, dpdv = map.dpdv;
        if (!m.tangents.empty()) {
          const Vec3 n = glm::length(corner.shading) > 0 ? glm::normalize(corner.shading) : facing;
          const glm::dvec4 own(Vec3(at(m.tangents)), m.tangents[t[0]].w);
          std::tie(dpdu, dpdv) = own_tangents(map, n, own);
          corner.mirrored = own.w < 0;
        }
        std::uint32_t id =
            sb.add_vertex(a + u * (b - a) + v * (c - a),
                          map.origin + u * map.along_b + v * map.along_c, dpdu, dpdv, corner);
        if (i == 0 && j == 0) g.first_vertex = id;
      }
    return g;
  };
  // A smooth mesh is one surface, welded throughout. A faceted one makes a surface of the
  // triangles of each plane (a box's face, however finely cut), welded where they meet, so
  // light is interpolated across the face, not flat per triangle, and only the creases
  // between planes are creases (near_field.h).
  std::vector<std::vector<std::size_t>> surfaces;
  if (m.smooth) {
    surfaces.emplace_back(m.triangles.size());
    std::iota(surfaces.back().begin(), surfaces.back().end(), std::size_t(0));
  } else {
    surfaces = coplanar_sets(m, size);
  }
  for (const std::vector<std::size_t>& triangles : surfaces) {
    sb.begin_surface(3 * triangles.size());
    std::vector<TriangleGrid> grids;
    for (std::size_t t : triangles) {
      if (sb.stopped()) return;
      grids.push_back(add_grid(m.triangles[t]));
    }
    sb.weld(!m.uvs.empty(), !m.normals.empty());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      if (sb.stopped()) return;
      emit(triangles[i], grids[i]);
    }
  }
  sb.flush();
}

// A sixteenth of the bounding-box diagonal of all objects: the scene's natural element size.
double sixteenth_of_diagonal(const Scene& scene) {
  Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const Object& o : scene.objects) {
    const auto [olo, ohi] = object_bounds(o);
    lo = glm::min(lo, olo);
    hi = glm::max(hi, ohi);
  }
  double diag = scene.objects.empty() ? 1.0 : glm::length(hi - lo);
  return diag > 0 ? diag / 16 : 1.0;
}

// Elements per patch side: the object's setting, else the scene's, else automatic: on flat
// shapes (quads, boxes) patches of about `patch_size` (the scene's natural element size)
// whatever the elements' size, at least 2 x 2, so that a finer mesh refines what receives
// light, not what shoots it. The Cornell box at 15 mm elements (8,992): 2 x 2 patches took
// 3,203 shots, 8.0 s; 4 x 4 patches 886 shots, 2.6 s, with the same image error against
// the path tracer.
int patch_elements(const Scene& scene, const Object& object, double element_size,
                   double patch_size) {
  if (object.density.patch_elements > 0) return object.density.patch_elements;
  if (scene.solver.patch_elements > 0) return scene.solver.patch_elements;
  // Curved surfaces keep small patches: one hemi-cube stands for a patch's whole face.
  const bool flat = std::holds_alternative<QuadShape>(object.shape) ||
                    std::holds_alternative<BoxShape>(object.shape);
  if (!flat || object.density.counts[0] > 0 || !(element_size > 0)) return 2;
  return std::max(2, int(std::lround(patch_size / element_size)));
}

}  // namespace

double Mesh::diagonal() const {
  return glm::length(bounds_max - bounds_min);
}

std::pair<Vec3, Vec3> object_bounds(const Object& object) {
  Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  auto grow = [&](const Vec3& p, double r) {
    lo = glm::min(lo, p - Vec3(r));
    hi = glm::max(hi, p + Vec3(r));
  };
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, QuadShape>) {
          for (const Vec3& p : s.corners) grow(p, 0);
        } else if constexpr (std::is_same_v<T, BoxShape>) {
          for (const Vec3& p : box_corners(s)) grow(p, 0);
        } else if constexpr (std::is_same_v<T, SphereShape>) {
          grow(s.center, s.radius);
        } else if constexpr (std::is_same_v<T, CylinderShape>) {
          grow(s.base, s.radius);
          grow(s.top, s.radius);
        } else {
          for (const Vec3& p : s.positions) grow(p, 0);
        }
      },
      object.shape);
  return {lo, hi};
}

double default_element_size(const Scene& scene) {
  return scene.solver.element_size > 0 ? scene.solver.element_size : sixteenth_of_diagonal(scene);
}

// A ball standing on a floor shades the floor within its own size, in direct light (exact
// per pixel in the view pass) and in the light the floor sends back up to the ball's
// underside, which elements larger than the ball spread flat over the shadow: the ball's
// bottom and the floor beside it came out 20-50 % too bright. So a quad that a smaller
// chunky object touches (its box meets the quad's plane, within a twentieth of its size,
// and the quad's box) is meshed at half that object's largest side, down to a quarter of
// the scene's size. Chunky: the shortest side of its box at least a quarter of the longest,
// so not a lamp's panel under a ceiling, a table's leg or a rug. Boxes are left as they are:
// their grids share one size, and a room built as one box would be refined on all six faces
// for what stands on its floor. bumprad-bench-scale's objects family (100 balls of
// 0.16-0.24 m on a floor in a 4 m room): its floor at 0.1 m instead of 0.4 m, 3.08 -> 2.51 %
// off the path tracer at 10k triangles, 3.30 -> 3.21 % at 90k (whose 1,000 shots then leave
// 8.9 % unshot, not 6.9 %).
std::vector<double> object_element_sizes(const Scene& scene) {
  const double size = default_element_size(scene);
  std::vector<double> out(scene.objects.size(), size);
  if (scene.solver.element_size > 0) return out;
  std::vector<std::pair<Vec3, Vec3>> bounds;
  struct Chunk {
    std::size_t index;
    double longest;
  };
  std::vector<Chunk> chunks;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    bounds.push_back(object_bounds(scene.objects[i]));
    Vec3 sides = bounds.back().second - bounds.back().first;
    std::sort(&sides[0], &sides[0] + 3);
    if (sides[2] > 0 && sides[0] >= 0.25 * sides[2]) chunks.push_back({i, sides[2]});
  }
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const auto* quad = std::get_if<QuadShape>(&scene.objects[i].shape);
    if (!quad) continue;
    const std::array<Vec3, 4>& p = quad->corners;
    const Vec3 normal = glm::cross(p[2] - p[0], p[3] - p[1]);
    if (!(glm::length(normal) > 0)) continue;
    const Vec3 n = glm::normalize(normal);
    const auto& [lo, hi] = bounds[i];
    for (const Chunk& chunk : chunks) {
      if (chunk.index == i || !(chunk.longest / 2 < out[i])) continue;
      const double gap = chunk.longest / 20;
      const auto& [clo, chi] = bounds[chunk.index];
      // The chunk's box's extent along the quad's normal, from the quad's plane.
      const Vec3 centre = (clo + chi) / 2.0, half = (chi - clo) / 2.0;
      const double along = glm::dot(centre - p[0], n), reach = glm::dot(half, glm::abs(n));
      if (std::abs(along) - reach <= gap && glm::all(glm::lessThanEqual(clo - Vec3(gap), hi)) &&
          glm::all(glm::lessThanEqual(lo, chi + Vec3(gap))))
        out[i] = std::max(size / 4, chunk.longest / 2);
    }
  }
  return out;
}

std::size_t estimate_element_count(const Object& object, double default_size) {
  double size = object.density.element_size > 0 ? object.density.element_size : default_size;
  if (const auto* m = std::get_if<TriangleMeshShape>(&object.shape)) {
    std::size_t total = 0;
    for (const auto& t : m->triangles) {
      bool valid =
          t[0] < m->positions.size() && t[1] < m->positions.size() && t[2] < m->positions.size();
      std::size_t n = valid ? std::size_t(triangle_subdivisions(*m, t, object.density, size)) : 1;
      total += n * n;
    }
    return total;
  }
  std::size_t total = 0;
  for (const Grid& g : grids_for(object, default_size))
    total += std::size_t(g.nu) * std::size_t(g.nv);
  return total;
}

namespace {

PatchEstimate object_patches(const Scene& scene, const Object& object, double size,
                             double patch_size) {
  const double object_size = object.density.element_size > 0 ? object.density.element_size : size;
  const std::size_t k = std::size_t(patch_elements(scene, object, object_size, patch_size));
  std::size_t total = 0;
  if (const auto* m = std::get_if<TriangleMeshShape>(&object.shape)) {
    // Triangles of one element cluster as mesh_triangles clusters them, into patches and
    // groups; a larger one makes patches of its own, k x k of its n x n elements each.
    std::unordered_set<std::uint64_t> cells, groups;
    for (const auto& t : m->triangles) {
      if (t[0] >= m->positions.size() || t[1] >= m->positions.size() || t[2] >= m->positions.size())
        continue;
      const std::size_t n = std::size_t(triangle_subdivisions(*m, t, object.density, object_size));
      const Vec3 a = m->positions[t[0]], b = m->positions[t[1]], c = m->positions[t[2]];
      if (n == 1) {
        const Vec3 centroid = (a + b + c) / 3.0, facing = glm::cross(b - a, c - a);
        cells.insert(cluster_key(centroid, facing, double(k) * object_size));
        groups.insert(cluster_key(centroid, facing, object_size));
      } else {
        total += std::max<std::size_t>(1, n * n / (k * k));
      }
    }
    return {total + cells.size(), double(k) * object_size, object_size, groups.size()};
  }
  // A grid's element side from its area (16 x 16 cells of its parametrisation): counts
  // given in the scene set it, not the element size.
  double area = 0, elements = 0;
  for (const Grid& g : grids_for(object, size)) {
    total += ((std::size_t(g.nu) + k - 1) / k) * ((std::size_t(g.nv) + k - 1) / k);
    elements += double(g.nu) * g.nv;
    constexpr int n = 16;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3 p = g.position(double(i) / n, double(j) / n);
        area += glm::length(glm::cross(g.position(double(i + 1) / n, double(j) / n) - p,
                                       g.position(double(i) / n, double(j + 1) / n) - p));
      }
  }
  const double element = std::sqrt(area / std::max(1.0, elements));
  return {total, double(k) * element, element, 0};
}

}  // namespace

std::vector<PatchEstimate> estimate_patches(const Scene& scene) {
  // Both sizes pass over every object's vertices: once for the scene, not once an object.
  const std::vector<double> sizes = object_element_sizes(scene);
  const double patch_size = sixteenth_of_diagonal(scene);
  std::vector<PatchEstimate> out;
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    out.push_back(object_patches(scene, scene.objects[i], sizes[i], patch_size));
  return out;
}

Mesh build_mesh(const Scene& scene, std::stop_token stop) {
  Mesh mesh;
  const std::vector<double> sizes = object_element_sizes(scene);
  const double patch_size = sixteenth_of_diagonal(scene);
  const double weld_tol =
      (scene.solver.element_size > 0 ? scene.solver.element_size : patch_size) * 1e-6;
  for (std::uint32_t oi = 0; oi < scene.objects.size() && !stop.stop_requested(); ++oi) {
    const Object& object = scene.objects[oi];
    const double size = sizes[oi];
    const double object_size = object.density.element_size > 0 ? object.density.element_size : size;
    const int k = patch_elements(scene, object, object_size, patch_size);
    SurfaceBuilder sb(mesh, object, oi, weld_tol, stop);
    if (const auto* m = std::get_if<TriangleMeshShape>(&object.shape)) {
      mesh_triangles(sb, *m, object.density, object_size, k);
    } else {
      for (const Grid& g : grids_for(object, size)) mesh_grid(sb, g, k);
    }
  }
  if (stop.stop_requested()) return mesh;

  // Vertex normals: area-weighted element normals; bounds from the vertices in use.
  mesh.bounds_min = Vec3(std::numeric_limits<double>::max());
  mesh.bounds_max = -mesh.bounds_min;
  for (const Element& e : mesh.elements)
    for (int i = 0; i < e.vertex_count; ++i) {
      Vertex& v = mesh.vertices[e.v[i]];
      v.normal += e.area * e.normal;
      mesh.bounds_min = glm::min(mesh.bounds_min, v.position);
      mesh.bounds_max = glm::max(mesh.bounds_max, v.position);
    }
  for (Vertex& v : mesh.vertices) {
    double len = glm::length(v.normal);
    if (len > 0) v.normal /= len;
  }
  if (mesh.elements.empty()) mesh.bounds_min = mesh.bounds_max = Vec3(0);
  // What the vectors grew by is a third of their size on average: at two million elements,
  // a few hundred megabytes.
  mesh.vertices.shrink_to_fit();
  mesh.elements.shrink_to_fit();
  mesh.patches.shrink_to_fit();
  mesh.groups.shrink_to_fit();
  return mesh;
}

}  // namespace bumprad
