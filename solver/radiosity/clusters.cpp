#include "solver/radiosity/clusters.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "solver/scene/geometry.h"
#include "solver/util/math.h"

namespace bumprad {
namespace {

// Whether the object's elements close up into a convex surface: every edge (by its welded
// vertices) is shared by exactly two of them, and neither has a corner more than `slack` in
// front of the other's plane. A closed surface convex at every edge is convex as a whole.
bool closed_and_convex(const Mesh& mesh, std::span<const std::uint32_t> elements, double slack) {
  auto in_front = [&](const Element& plane, const Element& other) {
    for (int k = 0; k < other.vertex_count; ++k)
      if (glm::dot(plane.normal, mesh.vertices[other.v[std::size_t(k)]].position - plane.centroid) >
          slack)
        return true;
    return false;
  };
  struct Sides {
    std::uint32_t first = 0;
    int count = 0;
  };
  std::unordered_map<std::uint64_t, Sides> edges;
  for (std::uint32_t i : elements) {
    const Element& e = mesh.elements[i];
    for (int k = 0; k < e.vertex_count; ++k) {
      const std::uint32_t a = e.v[std::size_t(k)], b = e.v[std::size_t((k + 1) % e.vertex_count)];
      Sides& s = edges[(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b)];
      if (s.count == 0) s.first = i;
      if (++s.count == 2) {
        const Element& o = mesh.elements[s.first];
        if (in_front(e, o) || in_front(o, e)) return false;
      }
    }
  }
  for (const auto& [edge, s] : edges)
    if (s.count != 2) return false;
  return true;
}

// One of 24 bins of the sphere of normals: the cube map face `n` leans on, in quarters.
std::size_t normal_bin(const Vec3& n) {
  const Vec3 a = glm::abs(n);
  const int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
  return std::size_t(8 * axis + 4 * (n[axis] > 0) + 2 * (n[(axis + 1) % 3] >= 0) +
                     (n[(axis + 2) % 3] >= 0));
}

// A cluster's patches are curved but for slivers: where a ball straddles the cells patches
// are cut by, a few of its triangles make a flat patch of their own.
constexpr double kCurvedShare = 0.9;
// And open but for slivers: a ball resting on a floor buries none of itself (its elements
// are open where most of their points are), a ball sunk into it half.
constexpr double kOpenShare = 0.99;

}  // namespace

// What a point at the centre can stand for. Convex: no part of the object lights another,
// so all it shoots leaves it, and every element faces away from the centre, where the
// hemi-cube culls the object's own faces as back faces. Curved: a uniformly bright ball,
// glowing or reflecting, lights everything wholly above its horizon exactly as a point at
// its centre would (Lambert), where a box's side face does not light the floor at its foot
// as its centre does. Small: it stands to its receivers as one of the scene's patches
// would. Open: a ball sunk into a block has its centre in the block.
std::vector<Cluster> find_clusters(const Mesh& mesh, const std::vector<Material>& materials,
                                   std::span<const double> open) {
  std::vector<std::vector<std::uint32_t>> patches_of, elements_of;
  for (std::uint32_t p = 0; p < mesh.patches.size(); ++p) {
    const std::uint32_t object = mesh.elements[mesh.patches[p].first].object;
    if (object >= patches_of.size()) patches_of.resize(object + 1), elements_of.resize(object + 1);
    patches_of[object].push_back(p);
    for (std::uint32_t e = 0; e < mesh.patches[p].count; ++e)
      elements_of[object].push_back(mesh.patches[p].first + e);
  }
  const double widest = mesh.diagonal() / 16;
  std::vector<Cluster> out;
  for (std::uint32_t object = 0; object < patches_of.size(); ++object) {
    const std::vector<std::uint32_t>& patches = patches_of[object];
    if (patches.size() < 2) continue;
    double curved_area = 0;
    for (std::uint32_t p : patches)
      curved_area += curved(mesh, mesh.patches[p]) ? mesh.patches[p].area : 0;
    bool fits = true;
    Vec3 centre(0);
    double area = 0, open_area = 0;
    for (std::uint32_t i : elements_of[object]) {
      const Element& e = mesh.elements[i];
      const Material& m = materials[std::size_t(e.material)];
      fits = fits && m.specular == 0;
      centre += e.area * e.centroid;
      area += e.area;
      open_area += e.area * (open.empty() ? 1 : open[i]);
    }
    if (!fits || !(curved_area >= kCurvedShare * area) || !(open_area >= kOpenShare * area))
      continue;
    centre /= area;
    double radius = 0;
    for (std::uint32_t i : elements_of[object])
      for (int k = 0; k < mesh.elements[i].vertex_count; ++k)
        radius = std::max(
            radius,
            glm::length(mesh.vertices[mesh.elements[i].v[std::size_t(k)]].position - centre));
    if (2 * radius > widest || !closed_and_convex(mesh, elements_of[object], 1e-4 * radius))
      continue;
    out.push_back({object, patches, centre, radius});
  }
  return out;
}

std::vector<Vec3> member_lobes(const Mesh& mesh, const Patch& patch,
                               std::span<const double> weight) {
  double total = 0;
  for (double w : weight) total += w;
  std::array<Vec3, 24> bins{};
  for (std::uint32_t k = 0; k < patch.count; ++k) {
    const Element& e = mesh.elements[patch.first + k];
    bins[normal_bin(e.normal)] += (total > 0 ? weight[k] : e.area) * e.normal;
  }
  double sum = 0;
  for (const Vec3& b : bins) sum += glm::length(b);
  std::vector<Vec3> out;
  for (const Vec3& b : bins)
    if (sum > 0 && glm::length(b) > 0) out.push_back(b / sum);
  return out;
}

double cluster_form_factor(const Mesh& mesh, std::span<const Vec3> lobes, const Vec3& centre,
                           const Element& e) {
  auto at = [&](const Vec3& x) {
    const Vec3 d = x - centre;
    const double r2 = glm::dot(d, d);
    if (!(r2 > 0)) return 0.0;
    const Vec3 w = d / std::sqrt(r2);
    const double cos_r = -glm::dot(e.normal, w);
    if (!(cos_r > 0)) return 0.0;
    double intensity = 0;
    for (const Vec3& lobe : lobes) intensity += std::max(0.0, glm::dot(lobe, w));
    return intensity * cos_r / (kPi * r2);
  };
  // Within a few of its sizes of the centre an element is not a point: a 0.5 m floor
  // element 0.2 m under a ball took 26 % too little at its centroid.
  const double distance = glm::length(e.centroid - centre);
  const int m = std::clamp(int(std::ceil(4 * std::sqrt(e.area) / distance)), 1, 8);
  if (m == 1) return at(e.centroid) * e.area;
  double f = 0;
  const std::vector<Vec3> points = part_points(mesh, e, m);
  for (const Vec3& x : points) f += at(x);
  return f * e.area / double(points.size());
}

}  // namespace bumprad
