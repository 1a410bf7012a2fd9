#include "solver/radiosity/vertex_radiosity.h"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "solver/scene/geometry.h"
#include "solver/util/frame.h"
#include "solver/util/parallel.h"

namespace bumprad {

std::vector<Rgb> vertex_radiosity(const Mesh& mesh, std::span<const Rgb> element_radiosity,
                                  std::span<const double> open) {
  // Open area first; a vertex among buried elements only takes their plain mean.
  std::vector<Rgb> sum(mesh.vertices.size(), Rgb(0)), buried(mesh.vertices.size(), Rgb(0));
  std::vector<double> area(mesh.vertices.size(), 0.0), buried_area(mesh.vertices.size(), 0.0);
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    const double w = open.empty() ? e.area : e.area * open[i];
    for (int k = 0; k < e.vertex_count; ++k) {
      sum[e.v[k]] += element_radiosity[i] * w;
      area[e.v[k]] += w;
      buried[e.v[k]] += element_radiosity[i] * e.area;
      buried_area[e.v[k]] += e.area;
    }
  }
  for (std::size_t v = 0; v < sum.size(); ++v)
    if (area[v] > 0)
      sum[v] /= area[v];
    else if (buried_area[v] > 0)
      sum[v] = buried[v] / buried_area[v];
  return sum;
}

namespace {

// The quarter of an element (quarter_points' order) that a hit at (u, v) lies in.
std::size_t quarter_of(const Element& e, double u, double v) {
  if (e.vertex_count == 4) return std::size_t(u >= 0.5) + 2 * std::size_t(v >= 0.5);
  if (u >= 0.5) return 1;
  if (v >= 0.5) return 2;
  return u + v >= 0.5 ? 3 : 0;
}

// The point of an element's 8 x 8 grid at ((a + 0.5) / 8, (b + 0.5) / 8).
Vec3 grid_point(const Mesh& mesh, const Element& e, int a, int b) {
  return point_at(mesh, e, (a + 0.5) / 8, (b + 0.5) / 8);
}

}  // namespace

std::vector<double> open_share(const Mesh& mesh, const RayScene& rays, std::stop_token stop) {
  return open_parts(mesh, rays, stop).share;
}

OpenParts open_parts(const Mesh& mesh, const RayScene& rays, std::stop_token stop) {
  const double epsilon = ray_epsilon(mesh);
  // A point on a non-planar quad may lie a little behind the two triangles Embree makes of
  // it: a ray that meets its own element first passes on from there.
  auto first_hit = [&](std::uint32_t self, Ray ray) {
    auto hit = rays.intersect(ray);
    if (hit && hit->element == self) {
      ray.origin += ray.direction * (hit->t + epsilon);
      hit = rays.intersect(ray);
    }
    return hit;
  };
  // Per element quarter (quarter_points' order): whether its point is open.
  const std::size_t quarters = 4 * mesh.elements.size();
  std::vector<std::uint8_t> state(quarters, 1);
  // Five rays from a point, along its normal and tilted 60 degrees four ways. A point none of
  // whose rays meets a back face is open. Otherwise it is open when two of them escape or
  // meet the lit side of an open quarter: inside a closed object every ray meets a back face,
  // and in a pocket closed off by a one-sided surface (the space under a terrain or a floor
  // slab that meets the walls) the rays that meet the walls and floor meet buried points.
  // Two, not one, so that a ray into the buried strip of an element whose quarter point lies
  // just above the seal does not open the pocket.
  struct Verdict {
    bool suspect = false, open = true;
  };
  // A quarter point's rays reach the quarter they meet; a point of the 8 x 8 grid below
  // (`fine`) reaches only elements open all over: the quarter an element cut by the seal
  // shows above it would open the pocket's points next to it.
  std::vector<std::uint8_t> whole;  // per element, for the grid: open all over
  auto judge = [&](std::uint32_t i, const Vec3& point, bool fine = false) {
    const Element& e = mesh.elements[i];
    const Frame frame = frame_about(e.normal);
    const Vec3 from = point + e.normal * epsilon;
    int reach = 0;
    Verdict verdict;
    for (int d = 0; d < 5; ++d) {
      const double phi = std::numbers::pi / 2 * d;
      const Vec3 local =
          d == 0 ? Vec3(0, 0, 1) : Vec3(0.866 * std::cos(phi), 0.866 * std::sin(phi), 0.5);
      const auto hit = first_hit(i, {from, frame.to_world(local)});
      if (hit && !hit->front) {
        verdict.suspect = true;
        continue;
      }
      reach +=
          !hit ||
          (fine
               ? whole[hit->element]
               : state[4 * hit->element + quarter_of(mesh.elements[hit->element], hit->u, hit->v)]);
    }
    verdict.open = !verdict.suspect || reach >= 2;
    return verdict;
  };
  // Suspect quarters start buried and open as what their rays reach opens (a few sweeps
  // reach a pocket's every point; each reads the sweep before, so the result does not
  // depend on the order of the work).
  // A grouped element (a model's triangle finer than the scene's elements, mesh.h) is first
  // judged at its centroid, its quarter points lying close by: where none of those five rays
  // meets a back face, its quarters are taken as unsuspected too. On the scale bench's four
  // families at 10k and 100k triangles the shares come out the same but for 40 of the 134k
  // figures' triangles (5.6 triangles' area in all), with a quarter of the rays.
  std::vector<std::uint8_t> suspect(quarters, 0);
  parallel_for(
      int(mesh.elements.size()),
      [&](int index) {
        const std::uint32_t i = std::uint32_t(index);
        const Element& e = mesh.elements[i];
        if (!mesh.groups.empty() && mesh.groups[e.group].count > 1 && !judge(i, e.centroid).suspect)
          return;
        const auto points = quarter_points(mesh, e);
        for (std::size_t q = 0; q < 4; ++q) suspect[4 * i + q] = judge(i, points[q]).suspect;
      },
      stop);
  for (std::size_t k = 0; k < quarters; ++k) state[k] = !suspect[k];
  for (int sweep = 0; sweep < 4; ++sweep) {
    std::vector<std::uint8_t> next = state;
    parallel_for(
        int(mesh.elements.size()),
        [&](int index) {
          const std::uint32_t i = std::uint32_t(index);
          if (!(suspect[4 * i] | suspect[4 * i + 1] | suspect[4 * i + 2] | suspect[4 * i + 3]))
            return;
          const auto points = quarter_points(mesh, mesh.elements[i]);
          for (std::size_t q = 0; q < 4; ++q)
            if (!state[4 * i + q]) next[4 * i + q] = judge(i, points[q]).open;
        },
        stop);
    if (next == state) break;
    state = std::move(next);
  }
  // An element whose quarters disagree, or that shares a vertex with one whose quarters
  // reach another verdict, is measured again on an 8 x 8 grid: the share divides the
  // element's radiosity (view_pass.cpp), and a strip buried along one edge (a wall below a
  // floor that meets it) can fall between the quarter points.
  std::vector<int> coarse(mesh.elements.size());
  std::vector<std::uint8_t> verdicts(mesh.vertices.size(), 0);  // bit 0: some open, 1: buried
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    coarse[i] = state[4 * i] + state[4 * i + 1] + state[4 * i + 2] + state[4 * i + 3];
    const Element& e = mesh.elements[i];
    const std::uint8_t bits = std::uint8_t((coarse[i] > 0 ? 1 : 0) | (coarse[i] < 4 ? 2 : 0));
    for (int k = 0; k < e.vertex_count; ++k) verdicts[e.v[std::size_t(k)]] |= bits;
  }
  std::vector<std::uint8_t> mixed(mesh.elements.size());
  whole.resize(mesh.elements.size());
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    mixed[i] = coarse[i] > 0 && coarse[i] < 4;
    for (int k = 0; k < e.vertex_count; ++k) mixed[i] |= verdicts[e.v[std::size_t(k)]] == 3;
    whole[i] = coarse[i] == 4 && !mixed[i];
  }
  OpenParts out;
  out.share.assign(mesh.elements.size(), 1.0);
  out.cells.assign(mesh.elements.size(), OpenParts::kWhole);
  parallel_for(
      int(mesh.elements.size()),
      [&](int index) {
        const std::size_t i = std::size_t(index);
        const Element& e = mesh.elements[i];
        if (!mixed[i]) {
          out.share[i] = coarse[i] / 4.0;
          return;
        }
        int inside = 0, open = 0;
        std::uint64_t cells = 0;
        for (int a = 0; a < 8; ++a)
          for (int b = 0; b < 8; ++b) {
            if (e.vertex_count == 3 && a + b > 7) continue;  // (u + v > 1)
            const Vec3 point = grid_point(mesh, e, a, b);
            ++inside;
            if (judge(std::uint32_t(i), point, true).open) {
              ++open;
              cells |= std::uint64_t(1) << (8 * a + b);
            }
          }
        out.share[i] = (coarse[i] > 0 ? std::max(1, open) : open) / double(inside);
        if (open > 0 && open < inside) out.cells[i] = cells;
      },
      stop);
  return out;
}

std::vector<Vec3> open_points(const Mesh& mesh, const Element& e, std::uint64_t cells) {
  std::vector<Vec3> out;
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b)
      if (cells >> (8 * a + b) & 1) out.push_back(grid_point(mesh, e, a, b));
  return out;
}

Vec3 open_centre(const Mesh& mesh, const OpenParts* open, std::uint32_t element) {
  const Element& e = mesh.elements[element];
  if (!open || !open->partly_open(element)) return e.centroid;
  Vec3 sum(0);
  const std::vector<Vec3> points = open_points(mesh, e, open->cells[element]);
  for (const Vec3& p : points) sum += p;
  return sum / double(points.size());
}

Rgb interpolate(const Element& e, std::span<const Rgb> values, double u, double v) {
  auto w = corner_weights(e, u, v);
  Rgb sum(0);
  for (int k = 0; k < e.vertex_count; ++k) sum += w[std::size_t(k)] * values[e.v[std::size_t(k)]];
  return sum;
}

}  // namespace bumprad
