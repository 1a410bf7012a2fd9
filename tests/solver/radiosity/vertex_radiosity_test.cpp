// Which part of each element is open to the scene, and vertex radiosity that leaves buried
// parts out: a box standing on a floor buries the floor beneath it, and the floor's vertices
// at the box's foot take the open floor's radiosity, not a mean with the dark buried floor.
#include "solver/radiosity/vertex_radiosity.h"

#include <cstdio>

#include <gtest/gtest.h>

#include "tests/test_scenes.h"

namespace bumprad {
namespace {

// A 2 x 2 floor of 4 x 4 elements (0.5 wide), and a unit-high box over x in [-1, x1],
// y in [-1, 0].
Scene floor_with_box(double x1) {
  Object box;
  box.shape = BoxShape{Vec3((x1 - 1) / 2, -0.5, 0.5), Vec3(x1 + 1, 1, 1), Vec3(0)};
  return test::scene_of(
      {test::quad({Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)}, 4, 4), box});
}

TEST(OpenShare, ABoxBuriesTheFloorBeneathIt) {
  for (double x1 : {0.0, -0.25}) {  // along element edges, and through the middle of some
    const Mesh mesh = build_mesh(floor_with_box(x1));
    const RayScene rays(mesh);
    const std::vector<double> open = open_share(mesh, rays);
    for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
      const Element& e = mesh.elements[i];
      if (e.object != 0) {
        EXPECT_EQ(open[i], 1) << "the box's own faces are open";
        continue;
      }
      const Vec3& c = e.centroid;
      const double covered_x = std::clamp((x1 - (c.x - 0.25)) / 0.5, 0.0, 1.0);
      const double expected = c.y < 0 ? 1 - covered_x : 1;
      EXPECT_DOUBLE_EQ(open[i], expected) << c.x << ", " << c.y << " box to x = " << x1;
    }
  }
}

// The same under a floor of fine triangles (a model's, received in groups): the floor's open
// area is what the box leaves, to 0.5 % of the floor (0.19 % and 0.05 % measured, the strip
// of grid cells along the box's foot), though its triangles' quarters are judged only where
// their centroid's rays meet a back face (every triangle open had they not been).
TEST(OpenShare, ABoxBuriesAFineFloorBeneathIt) {
  for (double x1 : {0.0, -0.33}) {
    Scene s = floor_with_box(x1);
    Object fine;
    TriangleMeshShape square = test::square_of_triangles(Vec3(0), 60, true);
    for (Vec3& p : square.positions) p = Vec3(-1, -1, 0) + 2.0 * p;
    fine.shape = square;
    s.objects[0] = fine;
    const Mesh mesh = build_mesh(s);
    ASSERT_GT(mesh.groups[mesh.elements[0].group].count, 1u) << "the floor is grouped";
    const RayScene rays(mesh);
    const std::vector<double> open = open_share(mesh, rays);
    double floor = 0, open_area = 0;
    for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
      if (mesh.elements[i].object != 0) continue;
      floor += mesh.elements[i].area;
      open_area += mesh.elements[i].area * open[i];
    }
    ASSERT_NEAR(floor, 4, 1e-9);
    EXPECT_NEAR(open_area, 4 - (x1 + 1), 0.005 * 4) << "box to x = " << x1;
    std::printf("box to x = %.2f: open %.5f of %.5f\n", x1, open_area, 4 - (x1 + 1));
  }
}

// A one-sided slab facing up across a closed room at 1.1 m closes off a pocket beneath it,
// as a terrain or a floor slab that meets the walls does: the walls' elements below it (and
// the room's floor) are buried, though the rays from the walls that meet the floor meet a
// front face; those it cuts are open above it only (6 of 8 grid rows above 1.1 in 1-1.5 m:
// 0.75, where the exact share is 0.8). Before, rays meeting any front face counted the
// point open, and the pocket's walls came out open: at a terrain's edge they darkened the
// wall above by their share of no light (a 10 m room of hills 5.6 % too dark, 3.8 % with
// them buried).
TEST(OpenShare, ASlabAcrossTheWallsBuriesThePocketBeneathIt) {
  const double w = 4, h = 4, slab = 1.1;
  Scene s = test::scene_of(
      {test::quad({Vec3(0, h, 0), Vec3(w, h, 0), Vec3(w, h, w), Vec3(0, h, w)}, 8, 8),
       test::quad({Vec3(0, h, w), Vec3(w, h, w), Vec3(w, 0, w), Vec3(0, 0, w)}, 8, 8),
       test::quad({Vec3(0, 0, 0), Vec3(w, 0, 0), Vec3(w, h, 0), Vec3(0, h, 0)}, 8, 8),
       test::quad({Vec3(0, h, 0), Vec3(0, h, w), Vec3(0, 0, w), Vec3(0, 0, 0)}, 8, 8),
       test::quad({Vec3(w, 0, 0), Vec3(w, 0, w), Vec3(w, h, w), Vec3(w, h, 0)}, 8, 8),
       test::quad({Vec3(0, 0, 0), Vec3(0, 0, w), Vec3(w, 0, w), Vec3(w, 0, 0)}, 8, 8),
       test::quad({Vec3(0, slab, 0), Vec3(0, slab, w), Vec3(w, slab, w), Vec3(w, slab, 0)}, 8, 8)});
  const Mesh mesh = build_mesh(s);
  const RayScene rays(mesh);
  const OpenParts parts = open_parts(mesh, rays);
  const std::vector<double>& open = parts.share;
  int pocket = 0, cut = 0;
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    if (e.object >= 5) {
      ASSERT_GT(e.normal.y, 0.5) << "the floor and the slab face up";
    }
    const double low = e.centroid.y - 0.25, high = e.centroid.y + 0.25;
    const bool wall = std::abs(e.normal.y) < 0.5;
    const double expected = e.object == 5 || (wall && high <= slab) ? 0
                            : wall && low < slab                    ? (high - slab) / 0.5
                                                                    : 1;
    EXPECT_NEAR(open[i], expected, 0.07) << "object " << e.object << " at " << e.centroid.x << ", "
                                         << e.centroid.y << ", " << e.centroid.z;
    // A cut element's open part is the strip above the slab (its centre to a grid cell, 1/16
    // of the element); elsewhere the element's centroid.
    if (wall && low < slab && high > slab)
      EXPECT_NEAR(open_centre(mesh, &parts, std::uint32_t(i)).y, (slab + high) / 2, 0.5 / 16);
    else
      EXPECT_EQ(open_centre(mesh, &parts, std::uint32_t(i)), e.centroid);
    pocket += wall && high <= slab;
    cut += wall && low < slab && high > slab;
  }
  EXPECT_EQ(pocket, 4 * 8 * 2);
  EXPECT_EQ(cut, 4 * 8);
}

// The Cornell box's red wall is a quad 3.2 mm out of plane: points spread over its
// bilinear elements lie a little behind the two triangles Embree makes of each, and rays
// from them met their own element's back. Nothing buries it.
TEST(OpenShare, ANonPlanarWallIsOpen) {
  for (double element_size : {30.0, 60.0}) {
    Scene s = test::scene_of({test::quad(
        {Vec3(552.8, 0, 0), Vec3(549.6, 0, 559.2), Vec3(556, 548.8, 559.2), Vec3(556, 548.8, 0)})});
    s.objects[0].density = MeshDensity{};
    s.solver.element_size = element_size;
    const Mesh mesh = build_mesh(s);
    const RayScene rays(mesh);
    for (double open : open_share(mesh, rays)) EXPECT_EQ(open, 1) << element_size;
  }
}

TEST(OpenShare, VerticesAtTheFootOfABoxTakeTheOpenFloor) {
  const Mesh mesh = build_mesh(floor_with_box(0));
  const RayScene rays(mesh);
  const std::vector<double> open = open_share(mesh, rays);
  std::vector<Rgb> b(mesh.elements.size());
  for (std::size_t i = 0; i < b.size(); ++i) b[i] = Rgb(open[i] > 0 ? 1 : 0);
  const std::vector<Rgb> plain = vertex_radiosity(mesh, b);
  const std::vector<Rgb> weighted = vertex_radiosity(mesh, b, open);
  std::vector<bool> on_floor(mesh.vertices.size(), false);
  for (const Element& e : mesh.elements)
    for (int k = 0; k < e.vertex_count; ++k) on_floor[e.v[std::size_t(k)]] = e.object == 0;
  int foot = 0;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3& p = mesh.vertices[v].position;
    if (!on_floor[v]) continue;
    const bool under = p.x < -1e-9 && p.y < -1e-9, edge = !under && p.x < 1e-9 && p.y < 1e-9;
    if (edge && p.x > -1 && p.y > -1) {
      ++foot;
      EXPECT_LT(plain[v].g, 1) << "a plain mean darkens the foot";
      EXPECT_DOUBLE_EQ(weighted[v].g, 1) << p.x << ", " << p.y;
    }
    if (under) {
      EXPECT_DOUBLE_EQ(weighted[v].g, 0) << "wholly buried: the buried mean";
    }
  }
  EXPECT_EQ(foot, 3);  // (0, -0.5), (0, 0) and (-0.5, 0)
}

}  // namespace
}  // namespace bumprad
