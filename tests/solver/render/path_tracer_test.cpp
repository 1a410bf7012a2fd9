// The ground-truth path tracer against closed forms: the furnace (a closed box of uniform E
// and rho is everywhere E / (pi (1 - rho))), Lambert's exact form factor for direct light,
// and a mirror's virtual image (Wallace, Cohen & Greenberg 1987) for light seen only
// through a planar mirror. Bounds are a few standard errors of the sample counts used.
#include "solver/render/path_tracer.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "solver/radiosity/form_factor_exact.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "tests/test_scenes.h"

namespace bumprad {
namespace {

constexpr double kPi = std::numbers::pi;

// A w x h rectangle centred at `c` in the plane z = c.z, facing +z (up) or -z (down).
Object rectangle(Vec3 c, double w, double h, bool up, int material) {
  std::array<Vec3, 4> p = {c + Vec3(-w / 2, -h / 2, 0), c + Vec3(w / 2, -h / 2, 0),
                           c + Vec3(w / 2, h / 2, 0), c + Vec3(-w / 2, h / 2, 0)};
  if (!up) std::swap(p[1], p[3]);
  Object o;
  o.shape = QuadShape{p};
  o.material = material;
  return o;
}

Material material(double rho, double emission, double specular = 0) {
  Material m;
  m.reflectance = Rgb(rho);
  m.emission = Rgb(emission);
  m.specular = specular;
  return m;
}

// A narrow camera (1 degree) at `from` looking at `at`: it sees a point's neighbourhood.
Camera pointing(Vec3 from, Vec3 at, int size = 8) {
  Camera c;
  c.position = from;
  c.look_at = at;
  c.up = Vec3(0, 0, 1);
  c.fov_y_deg = 1;
  c.width = c.height = size;
  return c;
}

Rgb mean(const Image& image) {
  Rgb sum(0);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) sum += image.at(x, y);
  return sum / double(image.width * image.height);
}

Image trace(const Scene& scene, int spp, std::uint64_t seed = 1) {
  Mesh mesh = build_mesh(scene);
  RayScene rays(mesh);
  return render_reference(scene, mesh, rays, {spp, seed});
}

TEST(PathTracer, FurnaceIsEmissionOverOneMinusRho) {
  for (double rho : {0.5, 0.8}) {
    Scene s;
    s.materials = {material(rho, 1)};
    Object box;
    box.shape = BoxShape{Vec3(0), Vec3(2, 2, 2), Vec3(0)};
    box.flip_normals = true;
    s.objects = {box};
    s.camera.position = Vec3(0.3, -0.4, 0.2);
    s.camera.look_at = Vec3(0, 1, 0);
    s.camera.width = s.camera.height = 16;
    const double expected = 1 / (kPi * (1 - rho));
    // 65,536 paths: measured 0.9991 (rho 0.5) and 1.0050 (rho 0.8); with 4 times as many,
    // 0.9969 and 0.9958.
    EXPECT_NEAR(mean(trace(s, 256)).g / expected, 1, 0.015) << "rho " << rho;
  }
}

TEST(PathTracer, DirectLightIsLambertsFormFactor) {
  Scene s;
  s.materials = {material(0.5, 0), material(0, 10)};
  const Object light = rectangle(Vec3(0, 0, 1), 1, 1, false, 1);
  s.objects = {rectangle(Vec3(0), 4, 4, true, 0), light};
  s.camera = pointing(Vec3(1.5, 0, 0.5), Vec3(0, 0, 0));
  const auto& corners = std::get<QuadShape>(light.shape).corners;
  const double f = point_to_polygon(Vec3(0), Vec3(0, 0, 1), corners);
  const double expected = 0.5 * 10 * f / kPi;
  // 16,384 paths with the light sampled at every one: measured 1.0060.
  EXPECT_NEAR(mean(trace(s, 256)).g / expected, 1, 0.01) << "F " << f;
}

// The receiver faces down beside a light that faces down too: it sees the light only in the
// mirror below them both, as the light's image under the floor.
TEST(PathTracer, LightThroughAPlanarMirrorIsItsVirtualImage) {
  Scene s;
  s.materials = {material(0, 0, 1), material(0, 10), material(0.5, 0)};
  const Object light = rectangle(Vec3(-0.7, 0, 1), 1, 1, false, 1);
  s.objects = {rectangle(Vec3(0), 6, 6, true, 0), light,
               rectangle(Vec3(0.7, 0, 1), 0.1, 0.1, false, 2)};
  s.camera = pointing(Vec3(0.7, -0.3, 0.6), Vec3(0.7, 0, 1), 16);
  std::array<Vec3, 4> image = std::get<QuadShape>(light.shape).corners;
  for (Vec3& p : image) p.z = -p.z;
  const double f = point_to_polygon(Vec3(0.7, 0, 1), Vec3(0, 0, -1), image);
  const double expected = 0.5 * 1.0 * 10 * f / kPi;  // rho k_s E F / pi
  // Next-event estimation through the mirror samples the image at every path: measured
  // 1.0114 at 16 paths a pixel (4,096 paths), 1.0026 at 64, 1.0007 at 4,096. (Before it,
  // only the 2 % of paths that happened to reflect into the image counted: 1.0040 at 4,096
  // paths a pixel.)
  EXPECT_NEAR(mean(trace(s, 64)).g / expected, 1, 0.02) << "F " << f;
}

// A small bright light in a wider glossy lobe: next-event estimation at the glossy surface,
// weighed against the lobe's own samples (multiple importance sampling), finds the highlight
// at every path. The lobe alone meets the light in ~5 % of paths: its pixels at 64 paths
// scattered by 69 %; with both, measured 2.0 % scatter and the mean within 0.2 %.
TEST(PathTracer, AGlossyHighlightIsExactAndQuiet) {
  const Scene s = test::glossy_highlight();
  const double expected = test::glossy_highlight_radiance(s);
  const Image image = trace(s, 64);
  const test::PixelSpread spread = test::pixel_spread(image);
  EXPECT_NEAR(spread.mean / expected, 1, 0.02);
  EXPECT_LT(spread.scatter, 0.1);
}

// An emission texture is what the camera sees of an emitter: E times its colour there
// (the light it sends stays E, evenly). A 4 x 4 emitter, its left half at 0.5 E, its right
// at 1.5 E, alone: each half's radiance is that over pi (to the image's single precision),
// at any path count.
TEST(PathTracer, AnEmissionTextureIsWhatTheCameraSees) {
  Scene s;
  s.materials = {material(0.5, 2)};
  s.materials[0].emission_texture = ColorTexture{};
  s.materials[0].emission_texture->colors = {Rgb(0.5), Rgb(1.5)};
  s.materials[0].emission_texture->scale = {2, 1};  // u < 1/2 and u > 1/2
  s.objects = {rectangle(Vec3(0), 4, 4, true, 0)};
  for (const double x : {-1.0, 1.0}) {
    s.camera = pointing(Vec3(x, -1, 2), Vec3(x, 0, 0));
    EXPECT_NEAR(mean(trace(s, 4)).g, 2 * (x < 0 ? 0.5 : 1.5) / kPi, 1e-6) << x;  // floats
  }
}

TEST(PathTracer, TheImageIsAFunctionOfTheSeed) {
  Scene s;
  s.materials = {material(0.5, 0), material(0, 10)};
  s.objects = {rectangle(Vec3(0), 4, 4, true, 0), rectangle(Vec3(0, 0, 1), 1, 1, false, 1)};
  s.camera = pointing(Vec3(1.5, 0, 0.5), Vec3(0, 0, 0), 4);
  Image a = trace(s, 4, 7), b = trace(s, 4, 7), c = trace(s, 4, 8);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_NE(a.rgb, c.rgb);
}

}  // namespace
}  // namespace bumprad
