// Punctual lights against closed forms: a point's I cos / r^2 and its shadow, a spot's cone,
// a sun's E cos; and, shone into the solve, a point over a floor element (I times the solid
// angle the element subtends, over its area) and a sun through a window (exactly the
// window's area of light on the floor, as the ledger's emitted power).
#include "solver/scene/punctual_light.h"

#include <array>
#include <cmath>
#include <numbers>
#include <stop_token>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "solver/radiosity/progressive.h"
#include "solver/render/path_tracer.h"
#include "solver/scene/geometry.h"
#include "solver/scene/mesh.h"
#include "solver/solution.h"
#include "tests/test_scenes.h"

namespace bumprad {
namespace {

// A floor in z = 0 facing up (+z), 4 x 4 centred on the origin, n x n elements.
Object floor_quad(int n) {
  return test::quad({Vec3(-2, -2, 0), Vec3(2, -2, 0), Vec3(2, 2, 0), Vec3(-2, 2, 0)}, n, n);
}

TEST(PunctualLight, PointSpotAndSunGiveTheirClosedForms) {
  Scene s = test::scene_of({floor_quad(1)});
  const Mesh mesh = build_mesh(s);
  const RayScene rays(mesh);
  PunctualLight point;
  point.position = Vec3(0, 0, 2);
  point.intensity = Rgb(3);
  const Vec3 up(0, 0, 1), x(1, 0.5, 0), from = x + up * 1e-6;
  const double r2 = 1 + 0.25 + 4, cosine = 2 / std::sqrt(r2);
  EXPECT_NEAR(punctual_irradiance(point, x, up, from, rays).g, 3 * cosine / r2, 1e-12);
  EXPECT_EQ(punctual_irradiance(point, x, -up, from, rays), Rgb(0)) << "from behind";
  // A tilted (perturbed) normal changes the cosine only.
  const Vec3 tilted = glm::normalize(Vec3(-1, 0, 1));
  const Vec3 d = glm::normalize(point.position - x);
  EXPECT_NEAR(punctual_irradiance(point, x, tilted, from, rays).g, 3 * glm::dot(tilted, d) / r2,
              1e-12);

  PunctualLight spot = point;
  spot.kind = PunctualLight::Kind::Spot;
  spot.direction = Vec3(0, 0, -1);
  spot.inner_cone_deg = 10;
  spot.outer_cone_deg = 30;
  // x is 29.2 degrees off the axis: ((cos 29.2 - cos 30) / (cos 10 - cos 30))^2 of it.
  const double c = 2 / std::sqrt(r2), outer = std::cos(30 * std::numbers::pi / 180),
               inner = std::cos(10 * std::numbers::pi / 180);
  const double falloff = std::pow((c - outer) / (inner - outer), 2);
  EXPECT_NEAR(punctual_irradiance(spot, x, up, from, rays).g, 3 * falloff * cosine / r2, 1e-12);
  EXPECT_EQ(punctual_irradiance(spot, Vec3(1.9, 0, 0), up, Vec3(1.9, 0, 1e-6), rays), Rgb(0))
      << "outside the cone";
  EXPECT_NEAR(punctual_power(spot).g, 2 * std::numbers::pi * (1 - outer) * 3, 1e-12);
  EXPECT_NEAR(punctual_power(point).g, 4 * std::numbers::pi * 3, 1e-12);

  PunctualLight sun;
  sun.kind = PunctualLight::Kind::Directional;
  sun.direction = glm::normalize(Vec3(1, 0, -1));
  sun.intensity = Rgb(2);
  EXPECT_NEAR(punctual_irradiance(sun, x, up, from, rays).g, 2 * std::sqrt(0.5), 1e-12);
}

TEST(PunctualLight, AShadowRayHidesWhatIsBehindSomething) {
  // A 1 x 1 blocker at z = 1 over the origin, facing down: the light at z = 2 is hidden from
  // the point under it, not from one far to the side.
  Scene s = test::scene_of({floor_quad(1), test::quad(test::rectangle_facing_down(1, 1, 1))});
  const Mesh mesh = build_mesh(s);
  const RayScene rays(mesh);
  PunctualLight point;
  point.position = Vec3(0, 0, 2);
  point.intensity = Rgb(1);
  const Vec3 up(0, 0, 1);
  EXPECT_EQ(punctual_irradiance(point, Vec3(0), up, Vec3(0, 0, 1e-6), rays), Rgb(0));
  EXPECT_GT(punctual_irradiance(point, Vec3(1.8, 0, 0), up, Vec3(1.8, 0, 1e-6), rays).g, 0);
}

// The floor (n x n elements, rho 0.5) under a point light 2 above its centre, I = 10 W/sr.
Scene point_lit_floor(int n) {
  Scene s = test::scene_of({floor_quad(n)}, 0.5);
  PunctualLight point;
  point.position = Vec3(0, 0, 2);
  point.intensity = Rgb(10);
  s.lights = {point};
  return s;
}

// The solid angle of the rectangle [0, a] x [0, b] seen from height h over its corner.
double corner_solid_angle(double a, double b, double h) {
  return std::atan(a * b / (h * std::sqrt(h * h + a * a + b * b)));
}

TEST(PunctualLight, ShoneIntoTheSolveAPointLightsEachElementBySolidAngle) {
  // 16 x 16 elements of 0.25; light 2 above the origin. An element's mean irradiance is
  // I Omega / A; the solve takes the mean over its four quarter points: within 0.5 % here.
  Scene s = point_lit_floor(16);
  const Mesh mesh = build_mesh(s);
  const RayScene rays(mesh);
  ProgressiveSolver solver(mesh, s.materials, s.solver, &rays);
  solver.shine(s.lights, rays);
  for (const Element& e : mesh.elements) {
    std::array<Vec3, 4> storage;
    const auto corners = element_corners(mesh, e, storage);
    Vec3 lo = corners[0], hi = corners[0];
    for (const Vec3& c : corners) lo = glm::min(lo, c), hi = glm::max(hi, c);
    // Omega of [lo, hi] by inclusion-exclusion of corner rectangles from the foot (0, 0).
    auto omega = [&](double x, double y) {
      return std::copysign(1.0, x) * std::copysign(1.0, y) *
             corner_solid_angle(std::abs(x), std::abs(y), 2);
    };
    const double solid =
        omega(hi.x, hi.y) - omega(lo.x, hi.y) - omega(hi.x, lo.y) + omega(lo.x, lo.y);
    const double expected = 0.5 * 10 * solid / e.area;  // rho I Omega / A
    EXPECT_NEAR(solver.direct()[std::size_t(&e - mesh.elements.data())].g, expected,
                0.005 * expected);
  }
  // Emitted 4 pi I; what misses the floor (most of it) escapes.
  const EnergyLedger l = solver.ledger();
  EXPECT_NEAR(l.emitted.g, 4 * std::numbers::pi * 10, 1e-9);
  EXPECT_NEAR(l.emitted.g, (l.absorbed + l.escaped + l.unshot).g, 1e-9 * l.emitted.g);
}

// A job stopped before its lights shine (a time limit, DELETE) shines nothing: on a large
// mesh the rays to a light are as many as four an element.
TEST(PunctualLight, AStoppedShineSendsNoLight) {
  Scene s = point_lit_floor(16);
  const Mesh mesh = build_mesh(s);
  const RayScene rays(mesh);
  std::stop_source stopped;
  stopped.request_stop();
  ProgressiveSolver solver(mesh, s.materials, s.solver, &rays, {}, stopped.get_token());
  solver.shine(s.lights, rays, stopped.get_token());
  EXPECT_EQ(solver.ledger().emitted.g, 0);
  for (const Rgb& d : solver.direct()) EXPECT_EQ(d.g, 0);
}

TEST(PunctualLight, ShoneThroughAWindowTheSunLightsTheWindowsAreaOfFloor) {
  // A roof at z = 1 facing down with a 1 x 1 window over [0, 1]^2 (four quads around it), the
  // sun straight down at E = 2: the floor receives 2 x 1 W, on the elements under the window
  // only (element edges on the window's: 0.25 grid).
  std::vector<Object> objects = {floor_quad(16)};
  auto roof = [&](double x0, double y0, double x1, double y1) {
    objects.push_back(
        test::quad({Vec3(x0, y0, 1), Vec3(x0, y1, 1), Vec3(x1, y1, 1), Vec3(x1, y0, 1)}));
  };
  roof(-2, -2, 0, 2);
  roof(1, -2, 2, 2);
  roof(0, -2, 1, 0);
  roof(0, 1, 1, 2);
  Scene s = test::scene_of(objects, 0.5);
  PunctualLight sun;
  sun.kind = PunctualLight::Kind::Directional;
  sun.direction = Vec3(0, 0, -1);
  sun.intensity = Rgb(2);
  s.lights = {sun};
  const Mesh mesh = build_mesh(s);
  const RayScene rays(mesh);
  ProgressiveSolver solver(mesh, s.materials, s.solver, &rays);
  solver.shine(s.lights, rays);
  EXPECT_NEAR(solver.ledger().emitted.g, 2.0, 1e-9);
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    if (e.object != 0) continue;
    const bool under = e.centroid.x > 0 && e.centroid.x < 1 && e.centroid.y > 0 && e.centroid.y < 1;
    EXPECT_NEAR(solver.direct()[i].g, under ? 0.5 * 2 : 0.0, 1e-12)
        << e.centroid.x << " " << e.centroid.y;
  }
}

TEST(PunctualLight, TheViewPassShowsAPointLightExactly) {
  // The floor (rho 0.5) under a point light 2 above it, I = 10 W/sr, seen from straight
  // above: the centre pixel is rho I / (pi h^2), nothing else lighting it.
  Scene s = point_lit_floor(8);
  s.camera.position = Vec3(0, 0, 1.5);
  s.camera.look_at = Vec3(0);
  s.camera.up = Vec3(0, 1, 0);
  s.camera.width = s.camera.height = 9;
  s.camera.antialias = 1;
  const Solution solution = solve(s);
  const Image image = render(s, solution);
  const double expected = 0.5 * 10 / (std::numbers::pi * 4);
  EXPECT_NEAR(image.at(4, 4).g, expected, 1e-4);
  // The path tracer (the ground truth the error estimate uses) agrees: its next event takes
  // the exact term, and Russian roulette keeps half the paths (rho 0.5), so over 81 pixels
  // of 1,024 paths the sums agree to about 0.35 % (one standard error); bound 2 %.
  ReferenceSettings reference;
  reference.samples_per_pixel = 1024;
  const Image traced = render_reference(s, *solution.mesh, *solution.rays, reference);
  double a = 0, b = 0;
  for (std::size_t i = 1; i < image.rgb.size(); i += 3) a += image.rgb[i], b += traced.rgb[i];
  EXPECT_NEAR(b / a, 1, 0.02);
}

}  // namespace
}  // namespace bumprad
