// Meshing: exact areas, outward normals, welded poles and seams, patch grouping, and the
// element-count estimate the parser relies on to refuse oversized scenes.
#include "solver/scene/mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "solver/util/random.h"
#include "tests/test_scenes.h"

namespace bumprad {
namespace {

double total_area(const Mesh& m) {
  double a = 0;
  for (const Element& e : m.elements) a += e.area;
  return a;
}

Scene one(Shape shape, MeshDensity d = {}) {
  Object o;
  o.shape = std::move(shape);
  o.density = d;
  return test::scene_of({o});
}

TEST(Mesh, QuadGridAreasPatchesAndSharedVertices) {
  Scene s = test::scene_of({test::quad(test::rectangle_facing_down(3, 2, 0), 6, 4)});
  s.objects[0].density.patch_elements = 2;
  Mesh m = build_mesh(s);
  EXPECT_EQ(m.elements.size(), 24u);
  EXPECT_EQ(m.patches.size(), 6u);
  EXPECT_EQ(m.vertices.size(), 35u);  // (6 + 1) x (4 + 1), shared
  EXPECT_NEAR(total_area(m), 6.0, 1e-12);
  for (const Patch& p : m.patches) {
    EXPECT_EQ(p.count, 4u);
    EXPECT_NEAR(p.area, 1.0, 1e-12);
    EXPECT_NEAR(p.normal.z, -1, 1e-12);
    for (std::uint32_t e = p.first; e < p.first + p.count; ++e)
      EXPECT_EQ(m.elements[e].patch, std::uint32_t(&p - m.patches.data()));
  }
}

TEST(Mesh, ElementSizeSetsTheGridAndTheDefaultIsCoarse) {
  Scene s = test::scene_of({test::quad(test::rectangle_facing_down(3, 2, 0), 0, 0)});
  s.objects[0].density.element_size = 0.5;
  EXPECT_EQ(build_mesh(s).elements.size(), 24u);
  s.objects[0].density.element_size = 0;
  // Default: a sixteenth of the diagonal, sqrt(13)/16 = 0.225: 14 x 9 elements.
  EXPECT_EQ(build_mesh(s).elements.size(), 126u);
  EXPECT_EQ(estimate_element_count(s.objects[0], default_element_size(s)), 126u);
}

// A quad that a smaller chunky object touches is meshed at half the object's largest side,
// down to a quarter of the scene's size (a sixteenth of the diagonal, about 0.35 m here): a
// 4 m floor with a ball of radius 0.1 on it takes 0.1 m, with one of radius 0.02 a quarter
// of the scene's size. A ball hovering 2 cm above the floor, a thin panel or a table's leg
// on it, a room built as one box, and a scene that sets its own size change nothing.
TEST(Mesh, AQuadASmallerChunkyObjectTouchesIsMeshedAtItsSize) {
  Object floor;
  floor.shape = QuadShape{{Vec3(0, 0, 0), Vec3(0, 0, 4), Vec3(4, 0, 4), Vec3(4, 0, 0)}};
  auto floor_size = [&](Shape other) {
    Object o;
    o.shape = std::move(other);
    const Scene s = test::scene_of({floor, o});
    const std::vector<double> sizes = object_element_sizes(s);
    EXPECT_EQ(sizes[1], default_element_size(s)) << "the other object keeps the scene's size";
    return sizes[0] / default_element_size(s);
  };
  const Scene alone = test::scene_of({floor});
  ASSERT_NEAR(default_element_size(alone), std::sqrt(32.0) / 16, 1e-12);
  EXPECT_NEAR(floor_size(SphereShape{Vec3(1, 0.1, 1), 0.1}) * default_element_size(alone), 0.1,
              0.001);
  EXPECT_EQ(floor_size(SphereShape{Vec3(1, 0.02, 1), 0.02}), 0.25);
  EXPECT_EQ(floor_size(SphereShape{Vec3(1, 0.12, 1), 0.1}), 1) << "hovering 2 cm above";
  EXPECT_EQ(floor_size(BoxShape{Vec3(1, 0.005, 1), Vec3(0.5, 0.01, 0.5)}), 1) << "a thin panel";
  EXPECT_EQ(floor_size(BoxShape{Vec3(1, 0.35, 1), Vec3(0.05, 0.7, 0.05)}), 1) << "a table's leg";
  Object room, ball;
  room.shape = BoxShape{Vec3(2, 1.5, 2), Vec3(4, 3, 4)};
  room.flip_normals = true;
  ball.shape = SphereShape{Vec3(1, 0.1, 1), 0.1};
  const Scene boxed = test::scene_of({room, ball});
  EXPECT_EQ(object_element_sizes(boxed)[0], default_element_size(boxed)) << "a room as one box";
  Scene set = test::scene_of({floor, ball});
  set.solver.element_size = 0.3;
  EXPECT_EQ(object_element_sizes(set), std::vector<double>(2, 0.3));
}

// Patches keep about the default element size (a sixteenth of the diagonal) when elements
// get finer, on flat shapes; curved ones and explicit settings keep their own.
TEST(Mesh, FinerElementsOnFlatShapesShareLargerPatches) {
  // A 3 x 2 quad: default size sqrt(13)/16 = 0.225; at 0.05, 60 x 40 elements, 4.5 a patch
  // side, rounded to 5: 12 x 8 patches.
  Scene s = test::scene_of({test::quad(test::rectangle_facing_down(3, 2, 0), 0, 0)});
  s.objects[0].density.patch_elements = 0;
  s.solver.element_size = 0.05;
  Mesh m = build_mesh(s);
  EXPECT_EQ(m.elements.size(), 2400u);
  EXPECT_EQ(m.patches.size(), 96u);
  s.solver.patch_elements = 2;
  EXPECT_EQ(build_mesh(s).patches.size(), 600u) << "the scene's setting wins";
  s.solver.patch_elements = 0;
  s.objects[0].density.patch_elements = 3;
  EXPECT_EQ(build_mesh(s).patches.size(), 20u * 14u) << "the object's setting wins";
  s.objects[0].density.patch_elements = 0;
  s.solver.element_size = 0.3;
  EXPECT_EQ(build_mesh(s).patches.size(), 20u)
      << "10 x 7 elements in 5 x 4 patches: never below 2 x 2";

  Scene ball = one(SphereShape{Vec3(0), 1}, {.element_size = 0.05});
  Mesh sphere = build_mesh(ball);
  double most = 0;
  for (const Patch& p : sphere.patches) most = std::max(most, double(p.count));
  EXPECT_LE(most, 4) << "curved patches stay 2 x 2";
}

TEST(Mesh, BoxNormalsPointOutwardOrInwardWhenFlipped) {
  BoxShape box{Vec3(1, 2, 3), Vec3(2, 1, 0.5), Vec3(10, 20, 30)};
  for (bool flip : {false, true}) {
    Scene s = one(box, {0, {2, 2}, 1});
    s.objects[0].flip_normals = flip;
    Mesh m = build_mesh(s);
    EXPECT_EQ(m.elements.size(), 24u);
    EXPECT_EQ(m.surface_count, 6u);
    EXPECT_NEAR(total_area(m), 2 * (2 * 1 + 2 * 0.5 + 1 * 0.5), 1e-12);
    for (const Element& e : m.elements)
      EXPECT_EQ(glm::dot(e.normal, e.centroid - box.center) > 0, !flip);
  }
}

TEST(Mesh, SphereIsClosedWeldedAndFacesOut) {
  SphereShape sphere{Vec3(0.5, 0, 0), 2};
  Mesh m = build_mesh(one(sphere, {0, {48, 24}, 2}));
  EXPECT_NEAR(total_area(m), 4 * std::numbers::pi * 4, 0.01 * 4 * std::numbers::pi * 4);
  EXPECT_EQ(m.surface_count, 1u);
  int triangles = 0;
  for (const Element& e : m.elements) {
    EXPECT_GT(glm::dot(e.normal, e.centroid - sphere.center), 0);
    EXPECT_GT(e.area, 0);
    triangles += e.vertex_count == 3;
  }
  EXPECT_EQ(triangles, 2 * 48);  // the rows at the poles
  // Each pole and each seam column is welded: every vertex is shared by a used element.
  std::vector<int> uses(m.vertices.size(), 0);
  for (const Element& e : m.elements)
    for (int k = 0; k < e.vertex_count; ++k) uses[e.v[k]]++;
  int used = 0;
  for (int u : uses) used += u > 0;
  EXPECT_EQ(used, 48 * 23 + 2);
}

TEST(Mesh, CylinderSideAndCapsShareTheRimButNotTheCrease) {
  CylinderShape c{Vec3(0), Vec3(0, 0, 2), 0.5, true};
  Mesh m = build_mesh(one(c, {0, {24, 4}, 1}));
  EXPECT_EQ(m.surface_count, 3u);
  double side = 2 * std::numbers::pi * 0.5 * 2, caps = 2 * std::numbers::pi * 0.25;
  EXPECT_NEAR(total_area(m), side + caps, 0.02 * (side + caps));
  for (const Element& e : m.elements) {
    Vec3 axial(0, 0, e.centroid.z - 1);
    Vec3 out = e.surface == 0 ? e.centroid - Vec3(0, 0, e.centroid.z) : axial;
    EXPECT_GT(glm::dot(e.normal, out), 0) << "surface " << e.surface;
  }
}

// Smooth meshes weld everywhere; faceted ones within each plane, so a flat face cut into
// triangles is one surface lit continuously, and a fold stays a crease.
TEST(Mesh, TriangleMeshSubdividesAndWeldsWithinAPlaneOrWhenSmooth) {
  TriangleMeshShape t;
  t.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  t.triangles = {{0, 1, 2}, {0, 2, 3}};
  auto used_vertices = [](const Mesh& m) {
    std::vector<int> uses(m.vertices.size(), 0);
    for (const Element& e : m.elements)
      for (int k = 0; k < e.vertex_count; ++k) uses[e.v[std::size_t(k)]]++;
    return std::count_if(uses.begin(), uses.end(), [](int u) { return u > 0; });
  };
  for (bool smooth : {false, true}) {
    t.smooth = smooth;
    t.positions[3].z = 0;
    Mesh m = build_mesh(one(t, {0, {3, 0}, 0}));
    EXPECT_EQ(m.elements.size(), 18u);
    EXPECT_NEAR(total_area(m), 1.0, 1e-12);
    for (const Element& e : m.elements) {
      EXPECT_EQ(e.vertex_count, 3);
      EXPECT_NEAR(e.normal.z, 1, 1e-12);
    }
    EXPECT_EQ(m.surface_count, 1u);
    EXPECT_EQ(used_vertices(m), 16);  // the diagonal's 4 points shared
    // Folded along the diagonal: two planes, a crease unless smooth.
    t.positions[3].z = 0.5;
    m = build_mesh(one(t, {0, {3, 0}, 0}));
    EXPECT_EQ(m.surface_count, smooth ? 1u : 2u);
    EXPECT_EQ(used_vertices(m), smooth ? 16 : 20);
  }
}

}  // namespace
}  // namespace bumprad

namespace bumprad {
namespace {
// Triangles finer than the element size are one element each; they shoot from patches of
// neighbouring triangles (cubes of two element sizes) and receive in groups (cubes of one),
// faceted or smooth, each group contiguous within its patch. Elsewhere (quads) every
// element is a group of its own.
TEST(Mesh, FineTrianglesShootFromPatchesAndReceiveInGroups) {
  for (bool smooth : {false, true}) {
    Scene s = one(test::square_of_triangles(Vec3(0), 40, smooth));
    s.solver.element_size = 0.1;
    const Mesh m = build_mesh(s);
    ASSERT_EQ(m.elements.size(), 3200u);
    EXPECT_LE(m.patches.size(), 36u);  // 5 x 5 cells, 6 x 6 where a cell edge falls off
    EXPECT_GE(m.groups.size(), 100u);
    EXPECT_LE(m.groups.size(), 121u);
    std::uint32_t next = 0;
    for (std::uint32_t g = 0; g < m.groups.size(); ++g) {
      const ElementGroup& group = m.groups[g];
      ASSERT_EQ(group.first, next) << "groups follow each other";
      next += group.count;
      const std::uint32_t patch = m.elements[group.first].patch;
      Vec3 lo(1e9), hi(-1e9);
      double area = 0;
      for (std::uint32_t i = group.first; i < group.first + group.count; ++i) {
        EXPECT_EQ(m.elements[i].group, g);
        EXPECT_EQ(m.elements[i].patch, patch) << "a group lies in one patch";
        lo = glm::min(lo, m.elements[i].centroid);
        hi = glm::max(hi, m.elements[i].centroid);
        area += m.elements[i].area;
      }
      EXPECT_LE(hi.x - lo.x, 0.1);
      EXPECT_LE(hi.y - lo.y, 0.1);
      EXPECT_NEAR(group.area, area, 1e-12);
      EXPECT_NEAR(group.normal.z, 1, 1e-12);
    }
    EXPECT_EQ(next, m.elements.size());
  }
  const Mesh quads =
      build_mesh(test::scene_of({test::quad(test::rectangle_facing_down(1, 1, 0), 4, 4)}));
  ASSERT_EQ(quads.groups.size(), quads.elements.size());
  for (std::uint32_t i = 0; i < quads.elements.size(); ++i) EXPECT_EQ(quads.elements[i].group, i);
}

// The vertices the elements use (welding leaves the others unused).
std::size_t used_vertices(const Mesh& m) {
  std::set<std::uint32_t> used;
  for (const Element& e : m.elements)
    for (int k = 0; k < e.vertex_count; ++k) used.insert(e.v[std::size_t(k)]);
  return used.size();
}

// One element per input triangle.
Scene whole(TriangleMeshShape m) {
  MeshDensity d;
  d.counts = {1, 0};
  return one(std::move(m), d);
}

// A model that repeats each triangle's corners (no shared indices) welds by position, to
// within a millionth of the element size: a 40 x 40 grid whose copies of a point differ by
// a tenth of that, in x for the odd triangles (the sweep along x must reach across them)
// and in y and z alone for the even ones (columns of one exact x, which the sweep leaves
// once y is past the tolerance), is one smooth surface of 41 x 41 vertices.
TEST(Mesh, RepeatedCornersWeldWithinTheTolerance) {
  const int n = 40;
  TriangleMeshShape m;
  m.smooth = true;
  Random random(11);
  const double jitter = 0.1 * 1e-6 * std::sqrt(2.0) / 16;  // a tenth of the weld tolerance
  auto at = [&](int i, int j, bool along_x) {
    auto shift = [&] { return jitter * (2 * random.next() - 1); };
    return Vec3(double(i) / n + (along_x ? shift() : 0), double(j) / n + shift(), shift());
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (const auto& corners : {std::array<std::array<int, 2>, 3>{{{0, 0}, {1, 0}, {1, 1}}},
                                  std::array<std::array<int, 2>, 3>{{{0, 0}, {1, 1}, {0, 1}}}}) {
        const bool odd = m.triangles.size() % 2 == 1;
        const auto first = std::uint32_t(m.positions.size());
        for (const auto& [di, dj] : corners) m.positions.push_back(at(i + di, j + dj, odd));
        m.triangles.push_back({first, first + 1, first + 2});
      }
  const Mesh mesh = build_mesh(whole(m));
  EXPECT_EQ(mesh.elements.size(), std::size_t(2 * n * n));
  EXPECT_EQ(mesh.surface_count, 1u);
  EXPECT_EQ(used_vertices(mesh), std::size_t((n + 1) * (n + 1)));
}

// A 2 x 1 rectangle in z = 0 facing up as two triangles over positions 0-3, with (u, v) the
// position scaled to [0,1]^2: the mesh's own parameterisation.
TriangleMeshShape uv_rectangle() {
  TriangleMeshShape m;
  m.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.smooth = true;
  return m;
}

TEST(Mesh, TriangleMeshUvsAreContinuousAcrossTrianglesWithTangentsThatFollowThem) {
  MeshDensity d;
  d.counts = {4, 0};  // 4 subdivisions a triangle edge
  const Mesh m = build_mesh(one(uv_rectangle(), d));
  // The grids of both triangles share the diagonal's 5 vertices: 15 + 15 - 5.
  EXPECT_EQ(used_vertices(m), 25u);
  for (const Vertex& v : m.vertices) {
    EXPECT_NEAR(v.uv.x, v.position.x / 2, 1e-12);
    EXPECT_NEAR(v.uv.y, v.position.y, 1e-12);
    EXPECT_NEAR(glm::length(v.dpdu - Vec3(2, 0, 0)), 0, 1e-12);
    EXPECT_NEAR(glm::length(v.dpdv - Vec3(0, 1, 0)), 0, 1e-12);
  }
}

TEST(Mesh, UvSeamsAndCreasesKeepTheirVerticesApart) {
  TriangleMeshShape seam = uv_rectangle();
  // Position 4 is position 2 again with other (u, v): the second triangle lies across a seam.
  seam.positions.push_back(seam.positions[2]);
  seam.uvs.push_back({0.5, 0.5});
  seam.triangles[1] = {0, 4, 3};
  EXPECT_EQ(used_vertices(build_mesh(whole(seam))), 5u);  // 4 welded to nothing
  TriangleMeshShape joined = uv_rectangle();
  EXPECT_EQ(used_vertices(build_mesh(whole(joined))), 4u);

  // Shading normals that disagree (a crease the model keeps sharp) split the shared edge.
  TriangleMeshShape crease = uv_rectangle();
  crease.uvs.clear();
  crease.positions.push_back(crease.positions[0]);
  crease.positions.push_back(crease.positions[2]);
  crease.triangles[1] = {4, 5, 3};
  crease.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0.6, 0.8}, {0, 0.6, 0.8}, {0, 0.6, 0.8}};
  EXPECT_EQ(used_vertices(build_mesh(whole(crease))), 6u);
  crease.normals.assign(6, {0, 0, 1});
  EXPECT_EQ(used_vertices(build_mesh(whole(crease))), 4u);
}

// The vertex at `position` that the elements use (the first one, if a seam keeps several).
const Vertex& vertex_at(const Mesh& m, const Vec3& position) {
  for (const Element& e : m.elements)
    for (int k = 0; k < e.vertex_count; ++k)
      if (glm::length(m.vertices[e.v[std::size_t(k)]].position - position) < 1e-12)
        return m.vertices[e.v[std::size_t(k)]];
  ADD_FAILURE() << "no vertex at the position";
  return m.vertices.front();
}

// A fan of five triangles around a centre whose (u, v) are stretched unevenly, so that each
// triangle's dp/du and dp/dv differ. The centre's tangents are MikkTSpace's: the triangles'
// directions weighted by the angle each spans at the centre, and their lengths likewise,
// whatever order the triangles come in (the first triangle's alone were kept before).
TEST(Mesh, ASmoothMeshsTangentsAreItsTrianglesAngleWeightedMean) {
  TriangleMeshShape fan;
  fan.smooth = true;
  fan.positions = {{0, 0, 0}, {1, 0, 0}, {0.3, 1, 0}, {-1, 0.6, 0}, {-0.7, -0.8, 0}, {0.4, -1, 0}};
  fan.uvs = {{0.5, 0.5}, {0.9, 0.45}, {0.6, 0.95}, {0.1, 0.7}, {0.2, 0.2}, {0.55, 0.1}};
  fan.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 1}};
  Vec3 du(0), dv(0);
  double length_u = 0, length_v = 0, angles = 0;
  for (const auto& t : fan.triangles) {
    const Vec3 e1 = fan.positions[t[1]] - fan.positions[t[0]];
    const Vec3 e2 = fan.positions[t[2]] - fan.positions[t[0]];
    const glm::dvec2 d1 = fan.uvs[t[1]] - fan.uvs[t[0]], d2 = fan.uvs[t[2]] - fan.uvs[t[0]];
    const double det = d1.x * d2.y - d1.y * d2.x;
    const Vec3 dpdu = (e1 * d2.y - e2 * d1.y) / det, dpdv = (e2 * d1.x - e1 * d2.x) / det;
    const double angle = std::acos(glm::dot(glm::normalize(e1), glm::normalize(e2)));
    du += angle * glm::normalize(dpdu), dv += angle * glm::normalize(dpdv);
    length_u += angle * glm::length(dpdu), length_v += angle * glm::length(dpdv);
    angles += angle;
  }
  const Vec3 want_u = glm::normalize(du) * (length_u / angles);
  const Vec3 want_v = glm::normalize(dv) * (length_v / angles);
  TriangleMeshShape reversed = fan;
  std::reverse(reversed.triangles.begin(), reversed.triangles.end());
  for (const TriangleMeshShape& shape : {fan, reversed}) {
    const Mesh m = build_mesh(whole(shape));
    ASSERT_EQ(used_vertices(m), 6u);
    const Vertex& centre = vertex_at(m, {0, 0, 0});
    EXPECT_NEAR(glm::length(centre.dpdu - want_u), 0, 1e-9 * glm::length(want_u));
    EXPECT_NEAR(glm::length(centre.dpdv - want_v), 0, 1e-9 * glm::length(want_v));
  }
}

// Two triangles whose (u, v) mirror each other across their shared edge, as a model's
// mirrored UV islands do: the edge's (u, v) agree, but the frames turn opposite ways, so its
// vertices stay apart and each triangle keeps its own tangents (averaged, they would cancel).
TEST(Mesh, MirroredUvIslandsKeepTheirOwnTangentsAlongTheirSeam) {
  TriangleMeshShape mirrored = uv_rectangle();
  mirrored.uvs[3] = {1, 0};  // position 3 reflected across the diagonal (0, 0)-(1, 1)
  const Mesh m = build_mesh(whole(mirrored));
  EXPECT_EQ(used_vertices(m), 6u);
  ASSERT_EQ(m.elements.size(), 2u);
  for (const Element& e : m.elements) {
    const bool first = e.centroid.y < e.centroid.x / 2;  // below the diagonal: {0, 1, 2}
    for (int k = 0; k < 3; ++k) {
      const Vertex& v = m.vertices[e.v[std::size_t(k)]];
      EXPECT_NEAR(glm::length(v.dpdu - (first ? Vec3(2, 0, 0) : Vec3(0, 1, 0))), 0, 1e-12);
      EXPECT_NEAR(glm::length(v.dpdv - (first ? Vec3(0, 1, 0) : Vec3(2, 0, 0))), 0, 1e-12);
    }
  }
}

// A model's own tangents (glTF's TANGENT) set the frame's directions, its (u, v) their
// lengths: tangents that agree with the (u, v) give the frame they give (the convention:
// w (n x t) points up the texture, against v), and tangents turned a quarter turn turn it.
TEST(Mesh, AMeshsOwnTangentsSetTheFramesDirections) {
  TriangleMeshShape m = uv_rectangle();
  m.normals.assign(4, {0, 0, 1});
  m.tangents.assign(4, {1, 0, 0, -1});
  for (const Vertex& v : build_mesh(whole(m)).vertices) {
    EXPECT_NEAR(glm::length(v.dpdu - Vec3(2, 0, 0)), 0, 1e-12);
    EXPECT_NEAR(glm::length(v.dpdv - Vec3(0, 1, 0)), 0, 1e-12);
  }
  m.tangents.assign(4, {0, 1, 0, 1});
  for (const Vertex& v : build_mesh(whole(m)).vertices) {
    EXPECT_NEAR(glm::length(v.dpdu - Vec3(0, 2, 0)), 0, 1e-12);
    EXPECT_NEAR(glm::length(v.dpdv - Vec3(1, 0, 0)), 0, 1e-12);
  }
  m.tangents.assign(4, {0, 1, 0, -1});
  for (const Vertex& v : build_mesh(whole(m)).vertices)
    EXPECT_NEAR(glm::length(v.dpdv - Vec3(-1, 0, 0)), 0, 1e-12);
}

}  // namespace
}  // namespace bumprad
