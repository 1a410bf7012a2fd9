// Progressive refinement: the furnace (a closed uniform enclosure converges to
// E / (1 - rho)) with hemi-cube and ray-cast form factors, the aliasing fallback, energy
// bookkeeping after every shot, and the step callback.
#include "solver/radiosity/progressive.h"

#include <cmath>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "solver/radiosity/clusters.h"
#include "solver/radiosity/form_factor_exact.h"
#include "solver/radiosity/vertex_radiosity.h"
#include "solver/scene/geometry.h"
#include "solver/scene/punctual_light.h"
#include "solver/scene/ray_scene.h"
#include "tests/test_scenes.h"

namespace bumprad {
namespace {

Scene furnace(double rho, double emission) {
  Object room;
  room.shape = BoxShape{Vec3(0), Vec3(1, 1.5, 2), Vec3(0, 25, 0)};
  room.flip_normals = true;
  room.density.element_size = 0.25;
  Scene s = test::scene_of({room}, rho, emission);
  s.solver.max_shots = 5000;
  s.solver.unshot_fraction = 1e-6;
  s.solver.hemicube_resolution = 100;
  return s;
}

TEST(Progressive, FurnaceConvergesToEmissionOverOneMinusRho) {
  for (double rho : {0.5, 0.8}) {
    Scene s = furnace(rho, 1.0);
    Mesh mesh = build_mesh(s);
    ProgressiveSolver solver(mesh, s.materials, s.solver);
    solver.run();
    ASSERT_LE(solver.unshot_fraction(), 1e-6);
    const double expected = 1.0 / (1 - rho);
    double worst = 0, mean = 0;
    for (const Rgb& b : solver.radiosity()) {
      worst = std::max(worst, std::abs(b.g - expected));
      mean += std::abs(b.g - expected) / double(mesh.elements.size());
    }
    std::printf("furnace rho=%.1f: %d shots, |B - E/(1-rho)| / B: worst %.2e, mean %.2e\n", rho,
                solver.shots(), worst / expected, mean / expected);
    // Shooting from patch centres is not exactly reciprocal. With the near-field
    // correction, measured worst / mean: 0.58% / 0.21% (rho 0.5), 0.89% / 0.34% (rho 0.8);
    // without it 7.5% / 4.0% at rho 0.5. Measured again 2026-12-05 (the code of 2026-12-04
    // gives the same): 1.21% / 0.28%, 1.48% / 0.45%, so the worst element at rho 0.8 is near
    // its bound; which change since moved it is not known.
    EXPECT_LT(worst, 0.015 * expected);
    EXPECT_LT(mean, 0.006 * expected);
    // Closed: nothing escapes but what falls between the pixels of edge-on seams.
    EnergyLedger l = solver.ledger();
    EXPECT_LT(l.escaped.g, 1e-3 * l.emitted.g);
  }
}

// A scene solved to 0.1 % unshot (at most 5,000 shots) as a job solves it, with its rays and
// open parts: the furnaces over grouped triangles below.
Scene to_a_thousandth(Scene s) {
  s.solver.unshot_fraction = 1e-3;
  s.solver.max_shots = 5000;
  return s;
}
struct Solved {
  explicit Solved(Scene s)
      : scene(to_a_thousandth(std::move(s))),
        mesh(build_mesh(scene)),
        rays(mesh),
        open(open_parts(mesh, rays)),
        solver(mesh, scene.materials, scene.solver, &rays, &open) {
    solver.run();
  }
  const Scene scene;
  const Mesh mesh;
  const RayScene rays;
  const OpenParts open;
  ProgressiveSolver solver;
};

// The furnace over hills: a closed room whose floor is one smooth mesh of rolling hills (its
// edges level with the walls' feet), everything emitting 1 with reflectance 0.5, so every
// element's radiosity is 2 however the light goes. The hills' triangles receive in groups
// and shoot from curved patches: a patch's points must face as its triangles do, and a
// valley's triangles light each other within one patch. Measured: 211 shots to 0.1 %
// unshot; over the hills' elements |B - 2| / 2 mean 0.72 %, worst 24.4 % (an element at a
// valley's crease), area-weighted mean B 0.994 of 2 (208, 0.70 %, 24.5 %, 0.996 while a near
// shooter's far elements gave Lambert's value, not a small patch's, 2026-12-07; 209, 0.76 %,
// 23 %, 0.994 before the groups' rays' difference from their pixels went to the rest of the
// room, 2026-12-07; 212, 0.88 %, 0.992 before a curved patch's neighbours took its near
// points' light, 2026-12-06). With every shooter point facing as its patch's mean normal,
// points off a curved patch's surface and no light within a patch (before 2026-12-05): 1.8 %
// still unshot after 5,000 shots, 2.7 %, 24 %, 0.973.
TEST(Progressive, FurnaceOverHillsConvergesToo) {
  const double side = 10, height = 4;
  Object ground;
  ground.shape = test::hills(40, side, [&](double u, double v) {
    const double x = side * u, z = side * v;
    const double rise =
        0.8 * std::sin(0.9 * x) * std::sin(0.7 * z) + 0.3 * std::cos(2.1 * x + 1.3 * z);
    return rise * (1 - std::pow(2 * u - 1, 8)) * (1 - std::pow(2 * v - 1, 8));
  });
  const double w = side, h = height;
  Solved f(test::scene_of(
      {ground, test::quad({Vec3(0, h, 0), Vec3(w, h, 0), Vec3(w, h, w), Vec3(0, h, w)}),
       test::quad({Vec3(0, h, w), Vec3(w, h, w), Vec3(w, 0, w), Vec3(0, 0, w)}),
       test::quad({Vec3(0, 0, 0), Vec3(w, 0, 0), Vec3(w, h, 0), Vec3(0, h, 0)}),
       test::quad({Vec3(0, h, 0), Vec3(0, h, w), Vec3(0, 0, w), Vec3(0, 0, 0)}),
       test::quad({Vec3(w, 0, 0), Vec3(w, 0, w), Vec3(w, h, w), Vec3(w, h, 0)})},
      0.5, 1));
  const Mesh& mesh = f.mesh;
  const ProgressiveSolver& solver = f.solver;
  ASSERT_LE(solver.unshot_fraction(), 1e-3);
  double mean = 0, worst = 0, light = 0, area = 0;
  int count = 0, grouped = 0;
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    if (e.object != 0) continue;
    grouped += mesh.groups[e.group].count > 1;
    const double error = std::abs(solver.radiosity()[i].g - 2) / 2;
    mean += error, worst = std::max(worst, error), ++count;
    light += solver.radiosity()[i].g * e.area, area += e.area;
  }
  mean /= count;
  ASSERT_GT(grouped, 0.9 * count) << "the hills' triangles receive in groups";
  std::printf("%d shots; hills' %d elements: |B - 2| / 2 mean %.3g, worst %.3g; mean B %.4f of 2\n",
              solver.shots(), count, mean, worst, light / area / 2);
  EXPECT_LT(mean, 0.015);
  EXPECT_LT(worst, 0.3);
  EXPECT_NEAR(light / area / 2, 1, 0.015);
}

// The furnace with balls: a closed 4 m room of quads and nine small balls of fine triangles
// on its floor, everything emitting 1 with reflectance 0.5, so B = 2 everywhere. The balls
// shoot as clusters (clusters.h): their light leaves their centres, which must neither make
// nor lose light, and land where their patches' own shots would have put it (reciprocity
// keeps B even). Measured: 29 shots to 0.1 % unshot; the balls' elements |B - 2| / 2 mean
// 1.31 %, worst 6.1 %, mean B 0.987 of 2; the room's mean 0.39 %, worst 1.3 %. With each of
// the balls' patches shooting alone (a temporary switch): 153 shots, 1.36 %, 6.2 %, 0.986;
// 0.39 %, 1.2 % (the balls' small shortfall is their groups', not the clusters').
TEST(Progressive, FurnaceWithBallsThatShootAsClusters) {
  const double w = 4, r = 0.12;
  std::vector<Object> objects = {
      test::quad({Vec3(0, 0, 0), Vec3(0, 0, w), Vec3(w, 0, w), Vec3(w, 0, 0)}),
      test::quad({Vec3(0, w, 0), Vec3(w, w, 0), Vec3(w, w, w), Vec3(0, w, w)}),
      test::quad({Vec3(0, w, w), Vec3(w, w, w), Vec3(w, 0, w), Vec3(0, 0, w)}),
      test::quad({Vec3(0, 0, 0), Vec3(w, 0, 0), Vec3(w, w, 0), Vec3(0, w, 0)}),
      test::quad({Vec3(0, w, 0), Vec3(0, w, w), Vec3(0, 0, w), Vec3(0, 0, 0)}),
      test::quad({Vec3(w, 0, 0), Vec3(w, 0, w), Vec3(w, w, w), Vec3(w, w, 0)})};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Object ball;
      ball.shape = test::ball(Vec3(1.2 + 0.8 * i, r, 1.2 + 0.8 * j), r, 16);
      objects.push_back(ball);
    }
  Solved f(test::scene_of(objects, 0.5, 1));
  ASSERT_EQ(find_clusters(f.mesh, f.scene.materials).size(), 9u);
  ASSERT_LE(f.solver.unshot_fraction(), 1e-3);
  struct Errors {
    double mean = 0, worst = 0, light = 0, area = 0;
    int count = 0;
  };
  Errors balls, room;
  for (std::size_t i = 0; i < f.mesh.elements.size(); ++i) {
    const Element& e = f.mesh.elements[i];
    Errors& to = e.object >= 6 ? balls : room;
    const double error = std::abs(f.solver.radiosity()[i].g - 2) / 2;
    to.mean += error, to.worst = std::max(to.worst, error), ++to.count;
    to.light += f.solver.radiosity()[i].g * e.area, to.area += e.area;
  }
  std::printf(
      "%d shots; balls' %d elements: |B - 2| / 2 mean %.3g, worst %.3g, mean B %.4f of 2; the "
      "room's mean %.3g, worst %.3g\n",
      f.solver.shots(), balls.count, balls.mean / balls.count, balls.worst,
      balls.light / balls.area / 2, room.mean / room.count, room.worst);
  EXPECT_LT(f.solver.shots(), 60) << "nine balls shoot as nine, not as their patches";
  EXPECT_LT(balls.mean / balls.count, 0.02);
  EXPECT_LT(balls.worst, 0.08);
  EXPECT_NEAR(balls.light / balls.area / 2, 1, 0.02);
  EXPECT_LT(room.mean / room.count, 0.006);
  EXPECT_LT(room.worst, 0.02);
}

// The furnace with a one-sided slab of fine triangles across the room, cutting a row of the
// walls' elements: beneath it a pocket of walls and floor that emit too, but whose light is
// trapped. Above it the room is closed, so B = E / (1 - rho) = 2 there. Buried parts used to
// emit all the same (a hemi-cube in the pocket sent their light through the slab's culled
// back): the slab came out 1.076 of 2. Measured: the slab's mean B 0.9997 of 2; the cut
// elements' reflected light over their open strip 0.91 of 1 (0.998 and 0.95 before the
// groups' rays' difference from their pixels went to the rest of the room, 2026-12-07: the
// open strip is measured on an 8 x 8 grid, 0.25 of the element where 0.2 is open).
TEST(Progressive, FurnaceOverASlabAcrossTheWalls) {
  Solved f(test::slab_across_a_closed_room(0.5, 1));
  const Mesh& mesh = f.mesh;
  const OpenParts& open = f.open;
  const ProgressiveSolver& solver = f.solver;
  ASSERT_LE(solver.unshot_fraction(), 1e-3);
  double slab_light = 0, slab_area = 0, cut_light = 0, cut_area = 0;
  int grouped = 0, count = 0, cut = 0;
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    if (e.object == 0) {
      grouped += mesh.groups[e.group].count > 1, ++count;
      slab_light += solver.radiosity()[i].g * e.area, slab_area += e.area;
    } else if (open.share[i] > 0 && open.share[i] < 1) {
      // The element's B is its area's mean: E over it all, the reflected light on the open
      // strip, a fifth of it (the 8 x 8 grid measures a quarter).
      cut_light += (solver.radiosity()[i].g - 1) * e.area, cut_area += 0.2 * e.area;
      ++cut;
    }
  }
  ASSERT_GT(grouped, 0.9 * count) << "the slab's triangles receive in groups";
  ASSERT_EQ(cut, 4 * 8);
  std::printf("%d shots; the slab's mean B / 2 %.4f; the cut elements' reflected light / 1 %.4f\n",
              solver.shots(), slab_light / slab_area / 2, cut_light / cut_area);
  EXPECT_NEAR(slab_light / slab_area / 2, 1, 0.015);
  EXPECT_NEAR(cut_light / cut_area, 1, 0.1);
}

// The furnace again with Wallace's ray-cast form factors: point sampling does not conserve
// energy (form factors from 16 samples per patch need not sum to one), so the closed box
// "leaks" a little and the radiosity settles low. Measured worst / mean: 0.28% / 0.22%
// (rho 0.5), 0.97% / 0.87% (rho 0.8); 0.44% and 1.1% of the emitted power escaped.
TEST(Progressive, FurnaceWithRayCastFormFactors) {
  for (double rho : {0.5, 0.8}) {
    Scene s = furnace(rho, 1.0);
    s.solver.form_factors = FormFactorMethod::RayCast;
    Mesh mesh = build_mesh(s);
    RayScene rays(mesh);
    ProgressiveSolver solver(mesh, s.materials, s.solver, &rays);
    solver.run();
    ASSERT_LE(solver.unshot_fraction(), 1e-6);
    const double expected = 1.0 / (1 - rho);
    double worst = 0, mean = 0;
    for (const Rgb& b : solver.radiosity()) {
      ASSERT_TRUE(std::isfinite(b.g));
      worst = std::max(worst, std::abs(b.g - expected));
      mean += std::abs(b.g - expected) / double(mesh.elements.size());
    }
    EnergyLedger l = solver.ledger();
    std::printf("ray-cast furnace rho=%.1f: worst %.2e, mean %.2e, escaped %.2e\n", rho,
                worst / expected, mean / expected, l.escaped.g / l.emitted.g);
    EXPECT_LT(worst, (rho < 0.6 ? 0.006 : 0.015) * expected);
    EXPECT_LT(mean, (rho < 0.6 ? 0.004 : 0.012) * expected);
    EXPECT_LT(l.escaped.g, (rho < 0.6 ? 0.01 : 0.02) * l.emitted.g);
    Rgb balance = l.absorbed + l.escaped + l.unshot;
    EXPECT_NEAR(balance.g, l.emitted.g, 1e-9 * l.emitted.g) << "the ledger still balances";
  }
  Scene s = furnace(0.5, 1.0);
  s.solver.form_factors = FormFactorMethod::RayCast;
  Mesh mesh = build_mesh(s);
  EXPECT_THROW(ProgressiveSolver(mesh, s.materials, s.solver), std::invalid_argument);
}

// Aliasing: a 5 cm receiver 10 m below a 1 m emitter covers 0.006 pixels of a 32-pixel
// hemi-cube, so the hemi-cube sees it in a whole pixel or not at all. Receivers that small
// take the ray-cast form factor instead (alias_pixels). Measured over 8 rotations: the
// hemi-cube alone missed it every time; with the fallback the worst error is 3.4e-5. The
// fallback's rays sample a shooter at 16 points at most: a lamp of 6 x 6 elements in one
// patch casts one ray per group of neighbours, not four per element (measured 2.2e-5).
TEST(Progressive, SmallDistantReceiversTakeRayCastFormFactors) {
  auto lamp = test::rectangle_facing_down(1, 1, 10);
  const double exact =
      point_to_polygon(Vec3(0), Vec3(0, 0, 1), std::vector<Vec3>(lamp.begin(), lamp.end())) *
      0.5;  // rho E F(dA -> lamp)
  for (int n : {1, 6}) {
    Object light = test::quad(lamp, n, n, 1);
    light.density.patch_elements = n;
    Scene s = test::scene_of({light, test::quad({Vec3(-0.025, -0.025, 0), Vec3(0.025, -0.025, 0),
                                                 Vec3(0.025, 0.025, 0), Vec3(-0.025, 0.025, 0)})},
                             0.5);
    s.materials.push_back(test::emitter(1));
    s.solver.hemicube_resolution = 32;
    Mesh mesh = build_mesh(s);
    ASSERT_EQ(mesh.patches.size(), 2u) << "the lamp is one patch";
    RayScene rays(mesh);
    std::uint32_t receiver = 0;
    while (mesh.elements[receiver].material != 0) ++receiver;
    for (double alias_pixels : {0.0, 4.0}) {
      if (n > 1 && alias_pixels == 0) continue;
      double worst = 0;
      for (std::uint32_t seed = 1; seed <= 8; ++seed) {
        s.solver.alias_pixels = alias_pixels;
        s.solver.seed = seed;
        ProgressiveSolver solver(mesh, s.materials, s.solver, &rays);
        ASSERT_TRUE(solver.shoot());
        worst = std::max(worst, std::abs(solver.radiosity()[receiver].g - exact) / exact);
      }
      std::printf("%d x %d lamp, alias_pixels %.0f: worst relative error over 8 rotations %.3g\n",
                  n, n, alias_pixels, worst);
      if (alias_pixels > 0)
        EXPECT_LT(worst, 1e-3);
      else
        EXPECT_GT(worst, 0.5) << "the failure this guards against";
    }
  }
}

// A floor of 7,200 small triangles (1.7 cm, finer than the 10 cm element size) 2 m under a
// lamp: each triangle covers a fifth of a hemi-cube pixel at resolution 150 (under a
// hundredth at 32), so alone it would get a whole pixel or none. Its group takes its
// visible share from rays, and each element its smooth unoccluded form factor times that
// share. Against Lambert's closed form per element, over 4 rotations, measured at both
// resolutions: worst 0.13 %, RMS 0.053 %, power 0.9996 of exact (from the group's pixels
// instead, at 150, they were 36 % and 9.2 %).
TEST(Progressive, FineTrianglesReceiveAsGroupsWithoutPixelNoise) {
  Object ground;
  ground.shape = test::square_of_triangles(Vec3(-0.5, -0.5, 0), 60, true);
  const auto lamp = test::rectangle_facing_down(0.5, 0.5, 2);
  Scene s = test::scene_of({test::quad(lamp, 1, 1, 1), ground}, 0.5);
  s.materials.push_back(test::emitter(1));
  s.solver.element_size = 0.1;
  Mesh mesh = build_mesh(s);
  ASSERT_EQ(mesh.elements.size(), 7201u);
  ASSERT_LT(mesh.groups.size(), 200u);
  RayScene rays(mesh);
  const std::vector<Vec3> outline(lamp.begin(), lamp.end());
  for (int resolution : {150, 32}) {
    double worst = 0, squares = 0, sum = 0, exact_sum = 0;
    int count = 0;
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
      s.solver.hemicube_resolution = resolution;
      s.solver.seed = seed;
      ProgressiveSolver solver(mesh, s.materials, s.solver, &rays);
      ASSERT_TRUE(solver.shoot());
      for (std::uint32_t i = 0; i < mesh.elements.size(); ++i) {
        const Element& e = mesh.elements[i];
        if (e.material != 0) continue;
        const double exact = 0.5 * point_to_polygon(e.centroid, e.normal, outline);
        const double got = solver.radiosity()[i].g;
        worst = std::max(worst, std::abs(got - exact) / exact);
        squares += (got - exact) * (got - exact) / (exact * exact);
        sum += got * e.area;
        exact_sum += exact * e.area;
        ++count;
      }
    }
    const double rms = std::sqrt(squares / count);
    std::printf("hemi-cube %d: per element worst %.3g, RMS %.3g; power received %.4f of exact\n",
                resolution, worst, rms, sum / exact_sum);
    EXPECT_LT(rms, 0.05);
    EXPECT_LT(worst, 0.15);
    EXPECT_NEAR(sum / exact_sum, 1, 0.02);
  }
}

// The fine floor above with a square between it and a lamp `lamp_side` across, 2 m up:
// each floor element's radiosity against exact. Exact: the lamp's form factor less that of
// the part of it the square hides, which from a point of the floor is the square's
// projection onto the lamp's plane clipped to the lamp (both are axis-aligned rectangles).
struct ShadowErrors {
  double rms, penumbra_rms, worst;  // relative to each element's unshadowed value
  int penumbra;                     // elements 2-98 % shadowed
};
ShadowErrors shadow_on_fine_floor(double lamp_side) {
  Object ground;
  ground.shape = test::square_of_triangles(Vec3(-0.5, -0.5, 0), 60, true);
  const auto lamp = test::rectangle_facing_down(lamp_side, lamp_side, 2);
  const double x0 = -0.2, x1 = 0.1, y0 = -0.2, y1 = 0.1, height = 0.5;
  Object square = test::quad(
      {Vec3(x0, y0, height), Vec3(x1, y0, height), Vec3(x1, y1, height), Vec3(x0, y1, height)}, 1,
      1, 2);
  Scene s = test::scene_of({test::quad(lamp, 1, 1, 1), ground, square}, 0.5);
  s.materials.push_back(test::emitter(1));
  s.materials.push_back(Material{});
  s.materials.back().reflectance = Rgb(0);
  s.solver.element_size = 0.1;
  Mesh mesh = build_mesh(s);
  RayScene rays(mesh);
  ProgressiveSolver solver(mesh, s.materials, s.solver, &rays);
  EXPECT_TRUE(solver.shoot());
  const std::vector<Vec3> outline(lamp.begin(), lamp.end());
  const double half = lamp_side / 2;
  double squares = 0, penumbra_squares = 0;
  ShadowErrors out{0, 0, 0, 0};
  int count = 0;
  for (std::uint32_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    if (e.object != 1) continue;
    const Vec3& p = e.centroid;
    auto onto_lamp = [&](double a, double pa) {
      return pa + (a - pa) * (2 - p.z) / (height - p.z);
    };
    const double hx0 = std::max(-half, onto_lamp(x0, p.x)),
                 hx1 = std::min(half, onto_lamp(x1, p.x));
    const double hy0 = std::max(-half, onto_lamp(y0, p.y)),
                 hy1 = std::min(half, onto_lamp(y1, p.y));
    const double open = 0.5 * point_to_polygon(p, e.normal, outline);
    double hidden = 0;
    if (hx0 < hx1 && hy0 < hy1) {
      const std::vector<Vec3> part{Vec3(hx0, hy0, 2), Vec3(hx0, hy1, 2), Vec3(hx1, hy1, 2),
                                   Vec3(hx1, hy0, 2)};
      hidden = 0.5 * point_to_polygon(p, e.normal, part);
    }
    const double error = (solver.radiosity()[i].g - (open - hidden)) / open;
    squares += error * error;
    out.worst = std::max(out.worst, std::abs(error));
    ++count;
    if (hidden > 0.02 * open && hidden < 0.98 * open)
      penumbra_squares += error * error, ++out.penumbra;
  }
  out.rms = std::sqrt(squares / count);
  out.penumbra_rms = std::sqrt(penumbra_squares / std::max(1, out.penumbra));
  std::printf(
      "lamp %.2f m: %d elements, %d in the penumbra: RMS %.3g (penumbra %.3g), worst %.3g "
      "of the unshadowed value\n",
      lamp_side, count, out.penumbra, out.rms, out.penumbra_rms, out.worst);
  return out;
}

// Each error under its bound, and more elements in the penumbra than the bound's count.
void expect_within(const ShadowErrors& e, const ShadowErrors& bound) {
  ASSERT_GT(e.penumbra, bound.penumbra);
  EXPECT_LT(e.rms, bound.rms);
  EXPECT_LT(e.penumbra_rms, bound.penumbra_rms);
  EXPECT_LT(e.worst, bound.worst);
}

// A 0.5 m lamp: the square's penumbra (0.17 m wide) spans about two groups, and within a
// group the shadow must change from element to element as the exact form factor does, not
// step at the group's edges. Measured: 1.7 % RMS, 3.2 % in the penumbra, 9.9 % worst (one
// visibility a group from four rays a lookout: 9.3 %, 18.5 %, 51 %).
TEST(Progressive, GroupedReceiversFollowAPenumbraAcrossEachGroup) {
  expect_within(shadow_on_fine_floor(0.5), {0.03, 0.05, 0.2, 1000});
}

// A lamp smaller than the scene's natural patch (0.12 m against 0.15 m) takes 16 rays a
// lookout, not 64. Its penumbra is 4 cm wide, under half a group, and four lookouts a group
// cannot follow it whatever their rays: measured 6.3 % RMS, 17 % in the penumbra, 46 % worst
// (with 64 rays 6.1 %, 15 %, 42 %). The exact direct light of the view pass draws such
// shadows; this is the light the floor reflects on.
TEST(Progressive, ASmallLampsShadowOnGroupsFromFewerRays) {
  expect_within(shadow_on_fine_floor(0.12), {0.075, 0.2, 0.55, 200});
}

// The floor the glowing-floor tests shoot from: 2 x 1 in z = 0, facing up, of nu x nv
// elements of material 1, all one patch.
Object glowing_floor(int nu, int nv) {
  Object floor =
      test::quad({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(0, 1, 0)}, nu, nv, 1);
  floor.density.patch_elements = nu;
  return floor;
}

// One shot of a scene whose floor glows: material 1 (glowing_floor's) emits 1 with
// reflectance `rho`; patches shoot from their open parts.
struct FirstShot {
  Mesh mesh;
  std::vector<Rgb> radiosity;
};
FirstShot shoot_once(Scene s, double rho) {
  Material glow;
  glow.reflectance = Rgb(rho);
  glow.emission = Rgb(1);
  s.materials.push_back(glow);
  FirstShot out{build_mesh(s), {}};
  const RayScene rays(out.mesh);
  const OpenParts open = open_parts(out.mesh, rays);
  ProgressiveSolver solver(out.mesh, s.materials, s.solver, &rays, &open);
  EXPECT_TRUE(solver.shoot());
  out.radiosity = solver.radiosity();
  return out;
}

// A glowing floor of one patch, a block across it and, beyond the block, a wall facing back
// towards the patch's centre, which the block hides from it: only the strip of floor
// between the block and the wall lights the wall. The hemi-cube at the centre sees none of
// the wall, which got nothing before; its rays from the patch's samples find the strip.
// Exact: the wall's mean of Lambert's form factor to the strip (256 points), times its
// reflectance. Measured: 1.10 of it (the points nearest the wall's foot, where the light is
// steepest, weigh a little heavy; 1.11 with all 800 quarter points); nothing at all before.
TEST(Progressive, ANearReceiverHiddenFromThePatchCentreIsLitByTheRestOfThePatch) {
  const Object floor = glowing_floor(20, 10);
  Object block;
  block.shape = BoxShape{Vec3(1.3, 0.5, 0.25), Vec3(0.2, 1, 0.5), Vec3(0)};
  Object wall =
      test::quad({Vec3(1.6, 0, 0), Vec3(1.6, 0, 0.3), Vec3(1.6, 1, 0.3), Vec3(1.6, 1, 0)}, 3, 10);
  Scene s = test::scene_of({floor, block, wall}, 0.5);
  s.solver.element_size = 0.1;
  const auto [mesh, radiosity] = shoot_once(s, 0);
  ASSERT_EQ(mesh.patches[mesh.elements[0].patch].count, 200u) << "the floor is one patch";
  double light = 0, area = 0;
  for (std::size_t i = 0; i < mesh.elements.size(); ++i)
    if (mesh.elements[i].object == 2) {
      ASSERT_LT(mesh.elements[i].normal.x, -0.99) << "the wall faces the patch's centre";
      light += radiosity[i].g * mesh.elements[i].area;
      area += mesh.elements[i].area;
    }
  const std::vector<Vec3> strip{Vec3(1.4, 0, 0), Vec3(1.6, 0, 0), Vec3(1.6, 1, 0), Vec3(1.4, 1, 0)};
  double exact = 0;
  for (int a = 0; a < 16; ++a)
    for (int b = 0; b < 16; ++b)
      exact += 0.5 *
               std::abs(point_to_polygon(Vec3(1.6, (a + 0.5) / 16, 0.3 * (b + 0.5) / 16),
                                         Vec3(-1, 0, 0), strip)) /
               256;
  std::printf("the wall's mean radiosity %.4g, exact %.4g\n", light / area, exact);
  EXPECT_NEAR(light / area / exact, 1, 0.15);
}

// The near field of a large patch: a glowing 2 x 1 m floor of 64 x 64 elements in one
// patch, and 0.1 m over it a ceiling of 16 x 16 elements facing down, every one of them
// near. The shooter's 16,384 quarter points are binned into 256 (near_points()), which
// took a shot from 10 s to 0.2 s. The hemi-cube's total stays as rendered (find()), so
// what is compared is how the light spreads: each ceiling element's share of what the
// ceiling receives against its share of the exact (its mean over 8 x 8 points of Lambert's
// form factor to the floor). Measured: RMS 0.090, worst 0.35 with the 256 points, and the
// same (0.090, 0.35) with all 16,384: what is left is the hemi-cube's visible share of
// receivers it sees 5 degrees above its horizon, not the binning; 16 points gave 0.71 and
// 1.4, 4 points 1.75 and 6.3.
TEST(Progressive, ALargePatchsNearFieldIsBoundedAndSpreadsItsLightAsAllItsPointsWould) {
  const Object floor = glowing_floor(64, 64);
  const Object ceiling =
      test::quad({Vec3(0, 0, 0.1), Vec3(0, 1, 0.1), Vec3(2, 1, 0.1), Vec3(2, 0, 0.1)}, 16, 16);
  Scene s = test::scene_of({floor, ceiling}, 0.5);
  const auto [mesh, radiosity] = shoot_once(s, 0);
  ASSERT_EQ(mesh.patches[mesh.elements[0].patch].count, 4096u) << "the floor is one patch";
  const std::vector<Vec3> outline{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(0, 1, 0)};
  std::vector<double> got, exact;
  for (const Element& e : mesh.elements) {
    if (e.object != 1) continue;
    std::array<Vec3, 4> storage;
    const std::span<const Vec3> corners = element_corners(mesh, e, storage);
    double f = 0;
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        const double u = (a + 0.5) / 8, v = (b + 0.5) / 8;
        const Vec3 p = (1 - u) * (1 - v) * corners[0] + u * (1 - v) * corners[1] +
                       u * v * corners[2] + (1 - u) * v * corners[3];
        f += point_to_polygon(p, e.normal, outline) / 64;
      }
    got.push_back(radiosity[std::size_t(&e - mesh.elements.data())].g);
    exact.push_back(f);
  }
  const double got_sum = std::accumulate(got.begin(), got.end(), 0.0);
  const double exact_sum = std::accumulate(exact.begin(), exact.end(), 0.0);
  double squares = 0, worst = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    const double error = (got[i] / got_sum) / (exact[i] / exact_sum) - 1;
    squares += error * error;
    worst = std::max(worst, std::abs(error));
  }
  const double rms = std::sqrt(squares / double(got.size()));
  std::printf("shares: RMS %.3g, worst %.3g over %zu elements\n", rms, worst, got.size());
  EXPECT_LT(rms, 0.1);
  EXPECT_LT(worst, 0.4);
}

// A model's fine triangles standing on a large patch of fine triangles: a glowing 1 x 1 m
// floor of 3,200 triangles (one patch) and, on its edge, a wall 0.5 m high facing it, of
// 400 triangles received in groups. Far from the floor a group's elements take their
// unoccluded form factors from the shooter's 16 ray samples; those misjudge the wall's foot,
// where the floor's nearest points give most of the light, so there they take Lambert's
// values from the shooter's 256 near points. Exact: each wall element's mean form factor to
// the floor (8 x 8 part points), times its reflectance (a half). Measured: RMS 7.2 % per
// element (21 % in the lowest row, whose centroids lie 1.7 cm from floor points 6 cm apart;
// 2.4 % at 0.1 m, under 1 % above 0.15 m), the lowest 0.1 m 2.3 % dark, power 0.1 % dark;
// from the 16 samples alone (in the triangles' order, before they were binned): 31.7 %, 65 %
// and 16 %.
TEST(Progressive, FineTrianglesStandingOnALargePatchTakeItsNearLightExactly) {
  Object floor;
  floor.shape = test::square_of_triangles(Vec3(0), 40, false);
  floor.material = 1;
  TriangleMeshShape wall;
  const int across = 20, up = 10;
  for (int j = 0; j <= up; ++j)
    for (int i = 0; i <= across; ++i)
      wall.positions.push_back(Vec3(1, double(i) / across, 0.5 * j / up));
  for (int j = 0; j < up; ++j)
    for (int i = 0; i < across; ++i) {
      const std::uint32_t a = std::uint32_t(j * (across + 1) + i), b = a + 1,
                          c = a + std::uint32_t(across + 1), d = c + 1;
      wall.triangles.push_back({a, c, b});  // facing -x, towards the floor
      wall.triangles.push_back({b, c, d});
    }
  Object standing;
  standing.shape = wall;
  Scene s = test::scene_of({floor, standing}, 0.5);
  s.solver.element_size = 1;
  const auto [mesh, radiosity] = shoot_once(s, 0);
  ASSERT_EQ(mesh.patches[mesh.elements[0].patch].count, 3200u) << "the floor is one patch";
  const std::vector<Vec3> outline{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  double squares = 0, got_power = 0, exact_power = 0, foot = 0, foot_exact = 0;
  int count = 0;
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    if (e.object != 1) continue;
    ASSERT_LT(e.normal.x, -0.99) << "the wall faces the floor";
    ASSERT_NE(mesh.groups[e.group].count, 1u) << "the wall's triangles receive in groups";
    double exact = 0;
    const std::vector<Vec3> points = part_points(mesh, e, 8);
    for (const Vec3& p : points) exact += 0.5 * point_to_polygon(p, e.normal, outline);
    exact /= double(points.size());
    const double got = radiosity[i].g;
    squares += (got - exact) * (got - exact) / (exact * exact);
    got_power += got * e.area;
    exact_power += exact * e.area;
    if (e.centroid.z < 0.1) foot += got * e.area, foot_exact += exact * e.area;
    ++count;
  }
  const double rms = std::sqrt(squares / count);
  std::printf("%d wall elements: RMS %.3g; the foot %.4f, all %.4f of exact\n", count, rms,
              foot / foot_exact, got_power / exact_power);
  EXPECT_LT(rms, 0.1);
  EXPECT_NEAR(foot / foot_exact, 1, 0.05);
  EXPECT_NEAR(got_power / exact_power, 1, 0.01);
}

// A glowing floor patch, half of it (and the patch's centre) under a block: the patch
// shoots from its open part, so a receiver behind the block, hidden from every open point
// of the floor, gets nothing. Shot from the patch centre, inside the block, the hemi-cube
// saw through the block's walls (their backs face it and are culled). The same for a floor
// of gently rolling triangles (a curved patch, its normals 4 degrees apart), which shot
// from its centre until 2026-12-06: the receiver got 4.1e-4 of light.
TEST(Progressive, APatchShootsFromItsOpenPartNotFromUnderABlock) {
  for (const bool rolling : {false, true}) {
    Object floor = glowing_floor(2, 1);
    if (rolling) {
      TriangleMeshShape m = test::square_of_triangles(Vec3(0), 10, true);
      for (Vec3& p : m.positions)
        p = Vec3(2 * p.x, p.y, 0.01 * std::sin(M_PI * p.x) * std::sin(M_PI * p.y));
      floor.shape = m;
      floor.density = {};
      floor.density.element_size = 0.25;
      floor.density.patch_elements = 20;
    }
    Object block;
    block.shape = BoxShape{Vec3(1.5, 0.5, 0.23), Vec3(1.2, 1.2, 0.5), Vec3(0)};
    block.density.counts = {2, 2};
    Object behind = test::quad(
        {Vec3(2.3, 0.4, 0.1), Vec3(2.3, 0.4, 0.3), Vec3(2.3, 0.6, 0.3), Vec3(2.3, 0.6, 0.1)});
    Scene s = test::scene_of({floor, block, behind}, 0.5);
    s.solver.hemicube_resolution = 64;
    const auto [mesh, radiosity] = shoot_once(s, 0.5);
    const Patch& patch = mesh.patches[mesh.elements[0].patch];
    ASSERT_EQ(patch.count, std::count_if(mesh.elements.begin(), mesh.elements.end(),
                                         [](const Element& e) { return e.object == 0; }))
        << "the floor is one patch";
    ASSERT_GT(patch.centroid.x, 0.9) << "under the block";
    double block_light = 0, behind_light = 0;
    for (std::size_t i = 0; i < mesh.elements.size(); ++i)
      (mesh.elements[i].object == 1 ? block_light : behind_light) +=
          mesh.elements[i].object == 0 ? 0 : radiosity[i].g * mesh.elements[i].area;
    std::printf("%s floor: light on the block %.3g, behind it %.3g\n", rolling ? "rolling" : "flat",
                block_light, behind_light);
    EXPECT_GT(block_light, 0.01);
    EXPECT_EQ(behind_light, 0.0);
  }
}

// A glowing floor patch of two 1 m elements, the second under a block, and a receiver above
// the open one that a 32-pixel hemi-cube sees in a fraction of a pixel, so rays from the
// patch give its form factor: 20 cm at 6 m, and 10 cm at 3 m, within the patch's near field
// (which the rays once skipped: the receiver got nothing). They weigh the patch's points by
// the power each shoots: the patch's power, E over its open element (the buried one's light
// is trapped under the block; it was shot from the open part too, 2 E, until the furnace
// over a slab showed a pocket's light getting out), leaves the open element, and the receiver
// (rho 0.5) gets rho E F(receiver -> open element), Lambert's closed form, within 2 %
// (weighed by the whole area, the buried element's rays, all hidden, took half of it away).
TEST(Progressive, RaysFromAHalfBuriedPatchCountItsOpenHalf) {
  for (const auto& [size, height] : {std::pair{0.2, 6.0}, std::pair{0.1, 3.0}}) {
    const Object floor = glowing_floor(2, 1);
    Object block;
    block.shape = BoxShape{Vec3(1.5, 0.5, 0.25), Vec3(1, 1.2, 0.5), Vec3(0)};
    block.density.counts = {2, 2};
    Object receiver = test::quad(test::rectangle_facing_down(size, size, height));
    for (Vec3& c : std::get<QuadShape>(receiver.shape).corners) c += Vec3(0.5, 0.5, 0);
    Scene s = test::scene_of({floor, block, receiver}, 0.5);
    s.solver.hemicube_resolution = 32;
    // Reflectance 0: nothing to overshoot, so the patch shoots just its E.
    const std::vector<Rgb> radiosity = shoot_once(s, 0).radiosity;
    const std::array<Vec3, 4> open = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    const double exact = 0.5 * point_to_polygon(Vec3(0.5, 0.5, height), Vec3(0, 0, -1), open);
    EXPECT_NEAR(radiosity.back().g / exact, 1, 0.02) << height << " m up";
  }
}

// A 2 x 1 m floor of one patch, lit at one end by a lamp, its other end under a block that
// floats 2 cm over it: open there (rays escape through the gap) but dark. Over the lit end
// hangs a ceiling of fine triangles, which receive as groups (from the patch's rays), and
// which the block hides from the floor beneath it. The floor's shot sends the ceiling the
// light of its lit end: each ceiling element's gain, exactly, is its reflectance times the
// sum over the floor's elements it sees of the radiosity each shoots times Lambert's form
// factor. Rays weighed by open area spread the patch's power over its dark end too, half of
// their samples hidden from the ceiling. Measured: 0.975 of it; 0.65 weighed by area.
TEST(Progressive, RaysFromAPatchLitAtOneEndLeaveFromThatEnd) {
  Object floor = test::quad({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(0, 1, 0)}, 20, 10);
  floor.density.patch_elements = 20;
  Object block;
  block.shape = BoxShape{Vec3(1.5, 0.5, 0.27), Vec3(1, 1.2, 0.5), Vec3(0)};
  Object ceiling;
  ceiling.shape = test::square_of_triangles(Vec3(0, 0, 1), 40, false);
  ceiling.flip_normals = true;
  ceiling.material = 1;
  Scene s = test::scene_of({floor, block, ceiling}, 0.8);
  s.materials.push_back(s.materials[0]);
  s.materials[1].reflectance = Rgb(0.2);
  PunctualLight lamp;
  lamp.position = Vec3(0.5, 0.5, 0.3);
  lamp.intensity = Rgb(1);
  s.lights = {lamp};
  const Mesh mesh = build_mesh(s);
  ASSERT_EQ(mesh.patches[mesh.elements[0].patch].count, 200u) << "the floor is one patch";
  const RayScene rays(mesh);
  const OpenParts open = open_parts(mesh, rays);
  ProgressiveSolver solver(mesh, s.materials, s.solver, &rays, &open);
  solver.shine(punctual_sources(s.lights, {}), rays);
  const std::vector<Rgb> before = solver.radiosity(), shoots = solver.display_radiosity();
  ASSERT_TRUE(solver.shoot());
  const std::vector<Rgb> after = solver.radiosity();
  const double offset = centroid_ray_offset(mesh);
  double got = 0, exact = 0, under = 0;
  for (std::uint32_t j = 0; j < mesh.elements.size(); ++j) {
    const Element& r = mesh.elements[j];
    if (r.object == 0 && r.centroid.x > 1.1) under += open.share[j] / 90;
    if (r.object != 2) continue;
    got += (after[j].g - before[j].g) * r.area;
    std::array<Vec3, 4> corners;
    for (std::uint32_t k = 0; k < mesh.elements.size(); ++k) {
      const Element& f = mesh.elements[k];
      if (f.object != 0) continue;
      const Vec3 from = r.centroid + r.normal * offset, to = f.centroid + f.normal * offset;
      if (rays.occluded({from, glm::normalize(to - from)}, glm::length(to - from))) continue;
      exact += 0.2 * shoots[k].g * r.area *
               point_to_polygon(r.centroid, r.normal, element_corners(mesh, f, corners));
    }
  }
  std::printf("floor beneath the block open %.2f; the ceiling's gain %.4g, exact %.4g (%.3f)\n",
              under, got, exact, got / exact);
  ASSERT_GT(under, 0.9) << "the floor beneath the block is open";
  EXPECT_NEAR(got / exact, 1, 0.05);
}

// A glowing 2 x 1 m floor of one patch and a ceiling of the same size over it, nothing
// else: open on every side, so what the ceiling receives is the floor's power times the
// closed form for parallel rectangles (Howell C-11), 0.29 at 1 m and 0.85 at 0.1 m.
// Every ceiling element is within the floor's near field. The hemi-cube at the floor's
// centre sees more of the ceiling than the floor's edges do: kept as its total, the
// ceiling got 26 % too much at 1 m and 13 % at 0.1 m. Measured: +0.1 % and -0.6 %.
TEST(Progressive, AnOpenSceneNearFieldDeliversWhatTheWholePatchSees) {
  for (const double height : {1.0, 0.1}) {
    const Object floor = glowing_floor(20, 10);
    const Object ceiling = test::quad(
        {Vec3(0, 0, height), Vec3(0, 1, height), Vec3(2, 1, height), Vec3(2, 0, height)}, 20, 10);
    Scene s = test::scene_of({floor, ceiling}, 0.5);
    const auto [mesh, radiosity] = shoot_once(s, 0);
    ASSERT_EQ(mesh.patches[mesh.elements[0].patch].count, 200u) << "the floor is one patch";
    double received = 0;
    for (std::size_t i = 0; i < mesh.elements.size(); ++i)
      if (mesh.elements[i].object == 1) received += radiosity[i].g * mesh.elements[i].area / 0.5;
    const double exact = 2 * parallel_rectangles(2, 1, height);
    std::printf("%.1f m: received %.4g, exact %.4g (%+.1f %%)\n", height, received, exact,
                100 * (received / exact - 1));
    EXPECT_NEAR(received / exact, 1, 0.02) << height << " m";
  }
}

// A lamp under a 2 x 2 ceiling, a floor 1 below: open on all four sides, so light escapes.
Scene open_plates() {
  auto floor = test::rectangle_facing_down(2, 2, 1);
  Scene s = test::scene_of({test::quad(test::rectangle_facing_down(0.4, 0.4, 0.99), 2, 2, 1),
                            test::quad({floor[3], floor[2], floor[1], floor[0]}, 6, 6, 0),
                            test::quad(test::rectangle_facing_down(2, 2, 1.01), 6, 6, 0)},
                           0.6);
  Material light;
  light.reflectance = Rgb(0.3, 0.5, 0.7);
  light.emission = Rgb(10, 20, 5);
  s.materials.push_back(light);
  s.objects[1].shape = QuadShape{{Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)}};
  return s;
}

TEST(Progressive, EnergyBalancesAfterEveryShotInAnOpenScene) {
  Scene s = open_plates();
  Mesh mesh = build_mesh(s);
  ProgressiveSolver solver(mesh, s.materials, s.solver);
  for (int shot = 0; shot < 150 && solver.shoot(); ++shot) {
    EnergyLedger l = solver.ledger();
    Rgb balance = l.absorbed + l.escaped + l.unshot;
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(balance[c], l.emitted[c], 1e-9 * l.emitted[c]) << shot;
  }
  EnergyLedger l = solver.ledger();
  EXPECT_GT(l.escaped.g, 0.01 * l.emitted.g);
  EXPECT_GT(l.absorbed.g, 0.01 * l.emitted.g);
}

// Overshooting leaves negative residuals (light sent ahead of arriving) that later shots
// take back, some of them negative: no element's radiosity may go below zero on the way,
// and the solve still reaches its target.
TEST(Progressive, OvershootingSendsLightAheadWithoutNegativeRadiosity) {
  Scene s = open_plates();
  s.solver.max_shots = 3000;
  s.solver.unshot_fraction = 1e-3;
  Mesh mesh = build_mesh(s);
  ProgressiveSolver solver(mesh, s.materials, s.solver);
  bool ahead = false;
  while (!solver.done() && solver.shoot()) {
    const EnergyLedger l = solver.ledger();
    const double signed_fraction =
        (l.unshot.r + l.unshot.g + l.unshot.b) / (l.emitted.r + l.emitted.g + l.emitted.b);
    ahead = ahead || solver.unshot_fraction() > signed_fraction + 1e-6;
    for (const Rgb& b : solver.radiosity())
      ASSERT_TRUE(b.r >= 0 && b.g >= 0 && b.b >= 0) << solver.shots();
  }
  EXPECT_TRUE(ahead) << "no residual ever went negative: nothing was overshot";
  EXPECT_LE(solver.unshot_fraction(), 1e-3);
  std::printf("open plates to 0.1 %% unshot: %d shots\n", solver.shots());
}

// The direct part of B is the first bounce of emission: in the furnace every element sees
// emitters all round, so it is rho E F summed to one, and over the box exactly rho times the
// emitted power the hemi-cubes saw (a closed box: all of it). The rest of B is E plus the
// indirect light, never negative.
TEST(Progressive, DirectPartIsTheFirstBounceOfEmission) {
  const double rho = 0.5, emission = 1;
  Scene s = furnace(rho, emission);
  Mesh mesh = build_mesh(s);
  ProgressiveSolver solver(mesh, s.materials, s.solver);
  solver.run();
  double direct_power = 0, area = 0, worst = 0;
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const double a = mesh.elements[i].area, d = solver.direct()[i].g;
    direct_power += d * a;
    area += a;
    worst = std::max(worst, std::abs(d / (rho * emission) - 1));
    EXPECT_GE(solver.radiosity()[i].g - emission - d, -1e-12) << i;
  }
  EXPECT_NEAR(direct_power / (rho * emission * area), 1, 1e-9);
  // Per element the hemi-cube's F sums to one up to the near-field redistribution.
  EXPECT_LT(worst, 0.05);
}

TEST(Progressive, AmbientTermLightsEarlyPreviewsAndVanishesAtConvergence) {
  Scene s = furnace(0.5, 1.0);
  Mesh mesh = build_mesh(s);
  ProgressiveSolver solver(mesh, s.materials, s.solver);
  // Before any shot, the ambient estimate already gives every element E / (1 - rho).
  for (const Rgb& b : solver.display_radiosity()) EXPECT_NEAR(b.g, 2.0, 1e-9);
  solver.run();
  auto display = solver.display_radiosity();
  for (std::size_t i = 0; i < display.size(); ++i)
    EXPECT_NEAR(display[i].g, solver.radiosity()[i].g, 1e-5);
}

// The ambient term stands in for the light not yet shot. In an open scene a share of every
// bounce leaves, and the term lets the unshot light leave in the same share: early in the
// solve (20 % unshot), the preview's reflected power is close to the converged solution's
// (measured +4.9 %), where Cohen's closed-room term, U / A / (1 - rho), over-predicts it
// (+51 %).
TEST(Progressive, AmbientTermPredictsTheConvergedLightOfAnOpenScene) {
  Scene s = open_plates();
  s.solver.max_shots = 100000;
  s.solver.unshot_fraction = 1e-5;
  Mesh mesh = build_mesh(s);
  double area = 0, rho_area = 0;
  for (const Element& e : mesh.elements) {
    area += e.area;
    rho_area += s.materials[std::size_t(e.material)].reflectance.g * e.area;
  }
  auto reflected = [&](const std::vector<Rgb>& b) {  // sum of (B - E) A, green
    double p = 0;
    for (std::size_t i = 0; i < b.size(); ++i)
      p += (b[i].g - s.materials[std::size_t(mesh.elements[i].material)].emission.g) *
           mesh.elements[i].area;
    return p;
  };
  ProgressiveSolver converged(mesh, s.materials, s.solver);
  converged.run();
  const double truth = reflected(converged.radiosity());

  ProgressiveSolver early(mesh, s.materials, s.solver);
  while (early.shots() < 3 || early.unshot_fraction() > 0.2) ASSERT_TRUE(early.shoot());
  const double shown = reflected(early.display_radiosity());
  const double closed = reflected(early.radiosity()) +
                        rho_area * early.ledger().unshot.g / area / (1 - rho_area / area);
  std::printf("unshot %.1f %%: shown %.4f, closed-room term %.4f of the converged light\n",
              100 * early.unshot_fraction(), shown / truth, closed / truth);
  EXPECT_NEAR(shown / truth, 1, 0.06);
  EXPECT_GT(closed / truth - 1, 3 * std::abs(shown / truth - 1));
}

TEST(Progressive, CallbackEveryStepCanStopTheSolve) {
  Scene s = furnace(0.5, 1.0);
  s.solver.preview_every = 7;
  Mesh mesh = build_mesh(s);
  ProgressiveSolver solver(mesh, s.materials, s.solver);
  std::vector<int> steps;
  solver.run([&](const Snapshot& snap) {
    EXPECT_EQ(snap.radiosity.size(), mesh.elements.size());
    steps.push_back(snap.shots);
    return snap.shots < 21;
  });
  EXPECT_EQ(steps, (std::vector<int>{7, 14, 21}));
  EXPECT_EQ(solver.shots(), 21);
}

TEST(Progressive, SameSeedSameSolution) {
  Scene s = furnace(0.7, 1.0);
  s.solver.max_shots = 40;
  Mesh mesh = build_mesh(s);
  ProgressiveSolver a(mesh, s.materials, s.solver), b(mesh, s.materials, s.solver);
  a.run();
  b.run();
  EXPECT_EQ(a.radiosity(), b.radiosity());
}

TEST(Progressive, NoEmissionIsDoneAtOnce) {
  Scene s = furnace(0.5, 0.0);
  Mesh mesh = build_mesh(s);
  ProgressiveSolver solver(mesh, s.materials, s.solver);
  EXPECT_TRUE(solver.done());
  EXPECT_FALSE(solver.shoot());
}

}  // namespace
}  // namespace bumprad
