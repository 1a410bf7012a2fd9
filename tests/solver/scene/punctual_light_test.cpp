// Punctual lights against closed forms: a point's I cos / r^2 and its shadow, a spot's cone,
// a sun's E cos; and, shone into the solve, a point over a floor element (I times the solid
// angle the element subtends, over its area) and a sun through a window (exactly the
// window's area of light on the floor, as the ledger's emitted power); their images in a
// planar mirror, and their highlights on a glossy surface.
#include "solver/scene/punctual_light.h"

#include <array>
#include <cmath>
#include <numbers>
#include <stop_token>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "solver/radiosity/progressive.h"
#include "solver/render/lights.h"
#include "solver/render/path_tracer.h"
#include "solver/scene/geometry.h"
#include "solver/scene/mesh.h"
#include "solver/scene/phong_lobe.h"
#include "solver/scene/planar_mirror.h"
#include "solver/solution.h"
#include "tests/test_scenes.h"

namespace bumprad {
namespace {

// The light itself, no mirror's image of it.
PunctualSource straight(const PunctualLight& l) {
  return {l, 0, std::nullopt};
}

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
  EXPECT_NEAR(punctual_irradiance(straight(point), x, up, from, rays).g, 3 * cosine / r2, 1e-12);
  EXPECT_EQ(punctual_irradiance(straight(point), x, -up, from, rays), Rgb(0)) << "from behind";
  // A tilted (perturbed) normal changes the cosine only.
  const Vec3 tilted = glm::normalize(Vec3(-1, 0, 1));
  const Vec3 d = glm::normalize(point.position - x);
  EXPECT_NEAR(punctual_irradiance(straight(point), x, tilted, from, rays).g,
              3 * glm::dot(tilted, d) / r2, 1e-12);

  PunctualLight spot = point;
  spot.kind = PunctualLight::Kind::Spot;
  spot.direction = Vec3(0, 0, -1);
  spot.inner_cone_deg = 10;
  spot.outer_cone_deg = 30;
  // x is 29.2 degrees off the axis: ((cos 29.2 - cos 30) / (cos 10 - cos 30))^2 of it.
  const double c = 2 / std::sqrt(r2), outer = std::cos(30 * std::numbers::pi / 180),
               inner = std::cos(10 * std::numbers::pi / 180);
  const double falloff = std::pow((c - outer) / (inner - outer), 2);
  EXPECT_NEAR(punctual_irradiance(straight(spot), x, up, from, rays).g, 3 * falloff * cosine / r2,
              1e-12);
  EXPECT_EQ(punctual_irradiance(straight(spot), Vec3(1.9, 0, 0), up, Vec3(1.9, 0, 1e-6), rays),
            Rgb(0))
      << "outside the cone";
  EXPECT_NEAR(punctual_power(spot).g, 2 * std::numbers::pi * (1 - outer) * 3, 1e-12);
  EXPECT_NEAR(punctual_power(point).g, 4 * std::numbers::pi * 3, 1e-12);

  PunctualLight sun;
  sun.kind = PunctualLight::Kind::Directional;
  sun.direction = glm::normalize(Vec3(1, 0, -1));
  sun.intensity = Rgb(2);
  EXPECT_NEAR(punctual_irradiance(straight(sun), x, up, from, rays).g, 2 * std::sqrt(0.5), 1e-12);
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
  EXPECT_EQ(punctual_irradiance(straight(point), Vec3(0), up, Vec3(0, 0, 1e-6), rays), Rgb(0));
  EXPECT_GT(punctual_irradiance(straight(point), Vec3(1.8, 0, 0), up, Vec3(1.8, 0, 1e-6), rays).g,
            0);
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

// The solid angle of a floor element (in z = 0) seen from `light` above the floor: its
// corner rectangles from the light's foot, by inclusion-exclusion.
double solid_angle(const Mesh& mesh, const Element& e, const Vec3& light) {
  std::array<Vec3, 4> storage;
  const auto corners = element_corners(mesh, e, storage);
  Vec3 lo = corners[0], hi = corners[0];
  for (const Vec3& c : corners) lo = glm::min(lo, c), hi = glm::max(hi, c);
  lo -= light;
  hi -= light;
  auto omega = [&](double x, double y) {
    return std::copysign(1.0, x) * std::copysign(1.0, y) *
           corner_solid_angle(std::abs(x), std::abs(y), light.z);
  };
  return omega(hi.x, hi.y) - omega(lo.x, hi.y) - omega(hi.x, lo.y) + omega(lo.x, lo.y);
}

TEST(PunctualLight, ShoneIntoTheSolveAPointLightsEachElementBySolidAngle) {
  // 16 x 16 elements of 0.25; light 2 above the origin. An element's mean irradiance is
  // I Omega / A; the solve takes the mean over its four quarter points: within 0.5 % here.
  Scene s = point_lit_floor(16);
  const Mesh mesh = build_mesh(s);
  const RayScene rays(mesh);
  ProgressiveSolver solver(mesh, s.materials, s.solver, &rays);
  solver.shine(punctual_sources(s.lights, {}), rays);
  for (const Element& e : mesh.elements) {
    const double expected = 0.5 * 10 * solid_angle(mesh, e, Vec3(0, 0, 2)) / e.area;
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
  ProgressiveSolver solver(mesh, s.materials, s.solver, &rays, nullptr, stopped.get_token());
  solver.shine(punctual_sources(s.lights, {}), rays, stopped.get_token());
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
  solver.shine(punctual_sources(s.lights, {}), rays);
  EXPECT_NEAR(solver.ledger().emitted.g, 2.0, 1e-9);
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    if (e.object != 0) continue;
    const bool under = e.centroid.x > 0 && e.centroid.x < 1 && e.centroid.y > 0 && e.centroid.y < 1;
    EXPECT_NEAR(solver.direct()[i].g, under ? 0.5 * 2 : 0.0, 1e-12)
        << e.centroid.x << " " << e.centroid.y;
  }
}

// The path tracer's image at 1,024 paths a pixel over the view pass's `image`: the ratio of
// their sums (green).
double traced_over_rendered(const Scene& s, const Solution& solution, const Image& image) {
  ReferenceSettings reference;
  reference.samples_per_pixel = 1024;
  const Image traced = render_reference(s, *solution.mesh, *solution.rays, reference);
  double a = 0, b = 0;
  for (std::size_t i = 1; i < image.rgb.size(); i += 3) a += image.rgb[i], b += traced.rgb[i];
  return b / a;
}

// The floor [-2, 1] x [-2, 2] (12 x 16 elements of 0.25, rho 0.5) under a point light 2 above
// the origin, I = 10 W/sr, beside a mirror (k_s 0.8, 2 high) standing in x = 1, facing the
// light: the light's image 2 above (2, 0) lights the floor too, with 0.8 I, through the
// mirror.
Scene mirrored_light() {
  Scene s = test::scene_of(
      {test::quad({Vec3(-2, -2, 0), Vec3(1, -2, 0), Vec3(1, 2, 0), Vec3(-2, 2, 0)}, 12, 16),
       test::quad({Vec3(1, -2, 0), Vec3(1, -2, 2), Vec3(1, 2, 2), Vec3(1, 2, 0)}, 4, 4, 1)},
      0.5);
  Material mirror;
  mirror.reflectance = Rgb(0);
  mirror.specular = 0.8;
  s.materials.push_back(mirror);
  PunctualLight point;
  point.position = Vec3(0, 0, 2);
  point.intensity = Rgb(10);
  s.lights = {point};
  return s;
}

TEST(PunctualLight, APlanarMirrorsImageOfALightLightsWhatSeesItThere) {
  const Scene s = mirrored_light();
  const Mesh mesh = build_mesh(s);
  const RayScene rays(mesh);
  const std::vector<PunctualSource> sources =
      punctual_sources(s.lights, planar_mirror_planes(mesh, s.materials));
  ASSERT_EQ(sources.size(), 2u);
  EXPECT_NEAR(glm::length(sources[1].light.position - Vec3(2, 0, 2)), 0, 1e-12);

  // At (0.5, 0) on the floor: I cos / r^2 from the light and 0.8 I cos / r^2 from its image,
  // whose ray meets the mirror at z = 2/3 and goes on to the light unhindered.
  const Vec3 x(0.5, 0, 0), up(0, 0, 1);
  auto irradiance = [&](const Vec3& light, double intensity) {
    const Vec3 d = light - x;
    return intensity * glm::normalize(d).z / glm::dot(d, d);
  };
  const Lights lights(mesh, s.materials, s.lights);
  EXPECT_NEAR(lights.direct(x, up, up, rays, {}).g,
              irradiance(Vec3(0, 0, 2), 10) + irradiance(Vec3(2, 0, 2), 8), 1e-9);

  // Shone into the solve, every floor element gets rho I (Omega + 0.8 Omega') / A, Omega'
  // its solid angle from the image (the whole floor sees it in the mirror): within 0.5 %,
  // as for the light alone. What the mirror reflects leaves the ledger's absorbed.
  ProgressiveSolver solver(mesh, s.materials, s.solver, &rays);
  solver.shine(sources, rays);
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    if (e.object != 0) continue;
    const double expected =
        0.5 * 10 *
        (solid_angle(mesh, e, Vec3(0, 0, 2)) + 0.8 * solid_angle(mesh, e, Vec3(2, 0, 2))) / e.area;
    EXPECT_NEAR(solver.direct()[i].g, expected, 0.005 * expected);
  }
  const EnergyLedger l = solver.ledger();
  EXPECT_NEAR(l.emitted.g, 4 * std::numbers::pi * 10, 1e-9);
  EXPECT_NEAR(l.emitted.g, (l.absorbed + l.escaped + l.unshot).g, 1e-9 * l.emitted.g);
}

TEST(PunctualLight, TheViewPassAndThePathTracerAgreeBesideAMirror) {
  // The floor seen from above, lit straight and through the mirror, and by the light it
  // sends to the mirror and back: the solve books the image's light as direct, the view pass
  // puts it back exactly, and the path tracer finds it by next-event estimation. Their sums
  // over 81 pixels of 1,024 paths agree to 0.04 % (0.5 % with the mirror black; one path
  // tracer standard error is about 0.4 %); bound 2 %.
  Scene s = mirrored_light();
  s.camera.position = Vec3(-0.5, 0, 3);
  s.camera.look_at = Vec3(-0.5, 0, 0);
  s.camera.up = Vec3(0, 1, 0);
  s.camera.fov_y_deg = 50;
  s.camera.width = s.camera.height = 9;
  const Solution solution = solve(s);
  const Image image = render(s, solution);
  EXPECT_NEAR(traced_over_rendered(s, solution, image), 1, 0.02);
}

TEST(PunctualLight, ASunsImageInAMirrorIsAParallelBeam) {
  // The sun going down at 45 degrees toward the mirror: its image goes away from it at 45
  // degrees, and a floor point that sees the mirror that way gets 0.8 E cos 45 from it.
  const Scene s = mirrored_light();
  const Mesh mesh = build_mesh(s);
  const RayScene rays(mesh);
  PunctualLight sun;
  sun.kind = PunctualLight::Kind::Directional;
  sun.direction = glm::normalize(Vec3(1, 0, -1));
  sun.intensity = Rgb(2);
  const std::vector<PunctualSource> sources =
      punctual_sources(std::vector<PunctualLight>{sun}, planar_mirror_planes(mesh, s.materials));
  ASSERT_EQ(sources.size(), 2u);
  const Vec3 x(0.5, 0, 0), up(0, 0, 1);
  EXPECT_NEAR(punctual_irradiance(sources[1], x, up, x + up * 1e-6, rays).g,
              0.8 * 2 * std::sqrt(0.5), 1e-12);
  // From the far end of the floor the image's ray passes over the mirror's top (z = 2).
  EXPECT_EQ(punctual_irradiance(sources[1], Vec3(-1.9, 0, 0), up, Vec3(-1.9, 0, 1e-6), rays),
            Rgb(0));
  // A sun going away from the mirror's front has no image in it.
  sun.direction = glm::normalize(Vec3(-1, 0, -1));
  EXPECT_EQ(
      punctual_sources(std::vector<PunctualLight>{sun}, planar_mirror_planes(mesh, s.materials))
          .size(),
      1u);
}

TEST(PunctualLight, AGlossySurfaceShowsAPointLightsHighlight) {
  // A glossy floor (k_s 1, Phong 20, no diffuse part) seen at 45 degrees, a point light of
  // I = 3 W/sr where the mirror direction points, sqrt(2) away: the highlight's radiance is
  // I lobe.pdf(d) / r^2. The view pass and the path tracer (both deterministic here: the
  // lobe meets nothing after) show it within 0.5 %; before, neither showed anything.
  Scene s = test::glossy_highlight();
  s.objects.pop_back();  // its area lamp
  PunctualLight point;
  point.position = Vec3(1, 0, 1);
  point.intensity = Rgb(3);
  s.lights = {point};
  const Vec3 eye = glm::normalize(s.camera.look_at - s.camera.position);
  const PhongLobe lobe(glm::reflect(eye, Vec3(0, 0, 1)), Vec3(0, 0, 1), s.materials[0].shininess);
  const double expected = 3 * lobe.pdf(glm::normalize(Vec3(1, 0, 1))) / 2;
  const Solution solution = solve(s);
  EXPECT_NEAR(test::pixel_spread(render(s, solution)).mean / expected, 1, 0.005);
  ReferenceSettings reference;
  reference.samples_per_pixel = 4;
  EXPECT_NEAR(
      test::pixel_spread(render_reference(s, *solution.mesh, *solution.rays, reference)).mean /
          expected,
      1, 0.005);
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
  EXPECT_NEAR(traced_over_rendered(s, solution, image), 1, 0.02);
}

}  // namespace
}  // namespace bumprad
