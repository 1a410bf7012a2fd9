// Speed against accuracy: the sweep behind docs/speed-accuracy.png (scripts/chart.sh).
//   build/bin/bumprad-bench-accuracy [point] [perturbed] [cornell] [wrinkled-box] [paper-room]
// Writes CSV rows `part,method,setting,seconds,error`:
//  - part "point": a point form factor against Lambert's exact value, over 200 random
//    receivers (tilted up to 60 degrees) below a 1.2 x 0.8 rectangle at distance ~1 ("far")
//    and ~0.15 ("near"). seconds: per form factor; error: mean |F - F_exact| / mean F_exact.
//    Methods: the hemi-cube at resolution R, and Wallace's ray casting with n x n samples.
//  - part "perturbed": the perturbed radiosity map, gathered or shot, with 9-65 sampled
//    normals, against the exact perturbed value (see perturbed_sweep). seconds: texture
//    work per map vertex.
//  - parts "cornell", "wrinkled-box" and (asked for by name) "paper-room": bumprad's images
//    and the path tracer's own against the path-traced ground truth (see image_sweep).
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "bench/truth_metrics.h"
#include "common/stopwatch.h"
#include "protocol/scene_source.h"
#include "solver/radiosity/form_factor_exact.h"
#include "solver/radiosity/hemicube.h"
#include "solver/radiosity/perturbed_map.h"
#include "solver/radiosity/progressive.h"
#include "solver/radiosity/ray_cast_form_factor.h"
#include "solver/render/path_tracer.h"
#include "solver/scene/mesh.h"
#include "solver/solution.h"
#include "solver/util/random.h"

namespace bumprad {
namespace {

struct Receiver {
  Vec3 point, normal;
  double angle;  // hemi-cube rotation
};

std::vector<Receiver> receivers(int count, std::uint32_t seed) {
  Random rng(seed);
  auto u = [](Random& r) { return 2 * r.next() - 1; };
  std::vector<Receiver> out;
  for (int t = 0; t < count; ++t) {
    Vec3 p(0.6 * u(rng), 0.4 * u(rng), 0.05 * u(rng));
    double tilt = (std::numbers::pi / 3) * (0.5 + 0.5 * u(rng));
    double az = std::numbers::pi * u(rng);
    out.push_back(
        {p, Vec3(std::sin(tilt) * std::cos(az), std::sin(tilt) * std::sin(az), std::cos(tilt)),
         std::numbers::pi * u(rng)});
  }
  return out;
}

// A w x h rectangle at height z facing down, as one element.
Scene rectangle_scene(double w, double h, double z) {
  Scene s;
  s.materials.push_back({});
  Object o;
  o.shape = QuadShape{{Vec3(-w / 2, -h / 2, z), Vec3(-w / 2, h / 2, z), Vec3(w / 2, h / 2, z),
                       Vec3(w / 2, -h / 2, z)}};
  o.density.counts = {1, 1};
  s.objects.push_back(o);
  return s;
}

void point_sweep(const char* regime, double z) {
  Scene scene = rectangle_scene(1.2, 0.8, z);
  Mesh mesh = build_mesh(scene);
  RayScene rays(mesh);
  const Element& e = mesh.elements[0];
  std::vector<Vec3> polygon;
  for (int k = 0; k < 4; ++k) polygon.push_back(mesh.vertices[e.v[std::size_t(k)]].position);
  const auto rs = receivers(200, 7);
  std::vector<double> exact;
  double mean_exact = 0;
  for (const Receiver& r : rs) {
    exact.push_back(point_to_polygon(r.point, r.normal, polygon));
    mean_exact += exact.back() / double(rs.size());
  }
  auto report = [&](const std::string& method, int setting, double seconds,
                    const std::vector<double>& f) {
    double err = 0;
    for (std::size_t i = 0; i < f.size(); ++i) err += std::abs(f[i] - exact[i]);
    std::printf("point-%s,%s,%d,%.4e,%.4e\n", regime, method.c_str(), setting,
                seconds / double(f.size()), err / double(f.size()) / mean_exact);
  };
  for (int res : {16, 32, 64, 128, 256, 512}) {
    Hemicube h(mesh, res);
    std::vector<double> f;
    auto t0 = Clock::now();
    for (const Receiver& r : rs) {
      h.render(r.point, frame_about(r.normal, r.angle), std::nullopt);
      double sum = 0;
      for (const VisibleElement& v : h.form_factors()) sum += v.form_factor;
      f.push_back(sum);
    }
    report("hemicube", res, seconds_since(t0), f);
  }
  // Embree's first query builds what it needs lazily: keep that out of the timings.
  ray_cast_form_factor(rs[0].point, rs[0].normal,
                       std::vector<AreaSample>{{e.centroid, e.area, e.normal}}, &rays, 1e-6);
  for (int n : {1, 2, 4, 8, 16}) {
    std::vector<AreaSample> samples;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        samples.push_back({Vec3(1.2 * ((i + 0.5) / n - 0.5), 0.8 * ((j + 0.5) / n - 0.5), z),
                           e.area / (n * n), e.normal});
    std::vector<double> f;
    auto t0 = Clock::now();
    constexpr int kRepeats = 50;  // a pass takes well under a millisecond: time many
    for (int rep = 0; rep < kRepeats; ++rep) {
      f.clear();
      for (const Receiver& r : rs)
        f.push_back(ray_cast_form_factor(r.point, r.normal, samples, &rays, 1e-6));
    }
    report("ray_cast", n * n, seconds_since(t0) / kRepeats, f);
  }
}

// Part "perturbed": B'(N') from the map against rho * E * F(dA -> light, N') exact, for a
// 10 cm receiver one unit below a 1 x 0.6 light, at 300 random normals tilted up to 45
// degrees (the outer ring), interpolated between the samples.
// seconds: the texture work; error: mean |B' - exact| / mean exact. Setting: numbers per
// colour channel a vertex stores: sampled normals (rings x azimuths + 1), or 18 spherical
// harmonics (bands 0-2 and 4, solver/radiosity/map_basis.h), gathered and shot alike.
void perturbed_sweep() {
  constexpr double kRho = 0.5;
  const std::array<Vec3, 4> light = {Vec3(-0.2, -0.4, 1), Vec3(-0.2, 0.2, 1), Vec3(0.8, 0.2, 1),
                                     Vec3(0.8, -0.4, 1)};
  const std::vector<Vec3> light_polygon(light.begin(), light.end());
  const double side = 0.1;
  Scene scene;
  Material grey, lamp;
  grey.reflectance = Rgb(kRho);
  lamp.reflectance = Rgb(0);
  lamp.emission = Rgb(1);
  scene.materials = {grey, lamp};
  Object receiver, emitter;
  receiver.shape = QuadShape{{Vec3(side / 2, -side / 2, 0), Vec3(side / 2, side / 2, 0),
                              Vec3(-side / 2, side / 2, 0), Vec3(-side / 2, -side / 2, 0)}};
  receiver.density.counts = {1, 1};
  emitter.shape = QuadShape{light};
  emitter.material = 1;
  emitter.density.counts = {16, 16};
  emitter.density.patch_elements = 1;
  scene.objects = {receiver, emitter};
  scene.solver.max_shots = 256;
  scene.solver.unshot_fraction = 0;
  // The map carries all the light here, as in the paper (with exact direct light it would
  // carry none of this direct-only scene's).
  scene.solver.direct_light = DirectLight::Radiosity;
  Mesh mesh = build_mesh(scene);

  Random rng(11);
  auto u = [](Random& r) { return r.next(); };
  std::vector<Vec3> normals;
  for (int i = 0; i < 300; ++i) {
    double tilt = std::acos(1 - u(rng) * (1 - std::cos(std::numbers::pi / 4)));
    double az = 2 * std::numbers::pi * u(rng);
    normals.emplace_back(std::sin(tilt) * std::cos(az), std::sin(tilt) * std::sin(az),
                         std::cos(tilt));
  }
  // Gather evaluates at the vertices, shoot over the receiving element (eq. 20): each is
  // compared with the exact value for what it computes.
  auto exact_at = [&](const Vec3& p, const Vec3& n) {
    return kRho * point_to_polygon(p, n, light_polygon);
  };
  auto exact_over_receiver = [&](const Vec3& n) {
    double sum = 0;
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j)
        sum += exact_at(Vec3(side * ((i + 0.5) / 8 - 0.5), side * ((j + 0.5) / 8 - 0.5), 0), n);
    return sum / 64;
  };
  // Sampled normals: rings of tilts times azimuths, plus N itself (9 to 65 in all); then
  // the harmonics.
  auto samples = [](std::vector<double> tilts_deg, int azimuths) {
    MapSettings s;
    s.basis = MapBasisKind::SampledNormals;
    s.tilts_deg = std::move(tilts_deg);
    s.azimuths = azimuths;
    return s;
  };
  const std::vector<MapSettings> bases = {samples({22.5, 45}, 4),
                                          samples({22.5, 45}, 8),  // the paper's, 17
                                          samples({15, 30, 45}, 8),
                                          samples({11.25, 22.5, 33.75, 45}, 8),
                                          samples({15, 30, 45}, 16),
                                          samples({11.25, 22.5, 33.75, 45}, 16),
                                          MapSettings{}};  // the default, 18 harmonics
  Hemicube warm_up(mesh, 150);  // the first gather pays for llvmpipe's shader compiles
  PerturbedMap(mesh, {true, false}, MapSettings{})
      .gather(scene.materials, std::vector<Rgb>(mesh.elements.size(), Rgb(0)), warm_up);
  for (const MapSettings& settings : bases) {
    for (TextureMode mode : {TextureMode::Gather, TextureMode::Shoot}) {
      PerturbedMap map(mesh, {true, false}, settings);
      double seconds = 0;
      if (mode == TextureMode::Gather) {
        std::vector<Rgb> radiosity(mesh.elements.size(), Rgb(0));
        for (std::size_t i = 0; i < mesh.elements.size(); ++i)
          if (mesh.elements[i].material == 1) radiosity[i] = Rgb(1);
        Hemicube hemicube(mesh, 150);
        auto t0 = Clock::now();
        map.gather(scene.materials, radiosity, hemicube);
        seconds = seconds_since(t0);
      } else {
        ProgressiveSolver solver(mesh, scene.materials, scene.solver);
        solver.attach_map(&map);
        solver.run();
        auto t0 = Clock::now();
        map.finish_shooting(scene.materials);
        seconds = seconds_since(t0) + solver.total_time().texture_s;
      }
      double err = 0, sum = 0;
      for (std::uint32_t slot = 0; slot < map.vertex_count(); ++slot) {
        const Vertex& v = mesh.vertices[map.vertex_of(slot)];
        Frame frame = tangent_frame(v.normal, v.dpdu);
        for (const Vec3& local : normals) {
          Vec3 n = frame.to_world(local);
          double exact =
              mode == TextureMode::Gather ? exact_at(v.position, n) : exact_over_receiver(n);
          err += std::abs(map.lookup(slot, local).g - exact);
          sum += exact;
        }
      }
      const bool sh = settings.basis == MapBasisKind::SphericalHarmonics;
      std::printf("perturbed,%s%s,%zu,%.4e,%.4e\n",
                  mode == TextureMode::Gather ? "gather" : "shoot", sh ? "_sh" : "",
                  map.basis().size(), seconds / double(map.vertex_count()), err / sum);
    }
  }
}

// Parts "cornell" and "wrinkled-box": images at 128 x 128 against the path-traced ground
// truth (solver/render/path_tracer.cpp, 16,384 paths a pixel, seed 1), in relative RMS over the lit
// surfaces with the reference's own noise taken out (bench/truth_metrics.h). Rows:
//  - path_tracer: the path tracer itself (seed 2) at 1 to 4,096 paths a pixel, its error
//    estimated the same way (the 4,096-path row, which measures the noise, is 2 sigma); setting:
//    paths a pixel. Its error against time is what bumprad has to beat.
//  - exact / radiosity (direct_light): bumprad's solve and render, to 3, 1 and 0.3 times the
//    scene's unshot fraction (1 % in cornell and wrinkled-box: 3 %, 1 %, 0.3 %) at its
//    element size, and to 0.3 times at twice and half of it; setting: elements. seconds:
//    solve and render, the time to the image.
void image_sweep(const std::string& name) {
  Scene base = load_scene("builtin:" + name);
  base.camera.width = base.camera.height = 128;
  // 4 x 4 rays a pixel, close to the path tracer's box-filtered pixels: at 128 x 128 the
  // edges of objects are a large share of the pixels, and coarser antialiasing would
  // measure their coverage rather than the lighting.
  base.camera.antialias = 4;
  const Mesh mesh = build_mesh(base);
  const RayScene rays(mesh);
  const std::vector<bool> emitter = emitter_pixels(base, mesh, rays);
  auto t0 = Clock::now();
  const Image reference = render_reference(base, mesh, rays, {16384, 1});
  std::fprintf(stderr, "%s: reference (16,384 paths a pixel) in %.0f s\n", name.c_str(),
               seconds_since(t0));
  // The path tracer at a quarter of the reference's paths is off by sqrt(4 + 1) times the
  // reference's noise; every row is printed with that noise taken out.
  struct Traced {
    int spp;
    double seconds, error;
  };
  std::vector<Traced> traced;
  for (int spp = 1; spp <= 4096; spp *= 4) {
    t0 = Clock::now();
    const Image image = render_reference(base, mesh, rays, {spp, 2});
    const double seconds = seconds_since(t0);
    traced.push_back({spp, seconds, compare(image, reference, emitter).surfaces});
  }
  const double noise = traced.back().error / std::sqrt(5.0);
  std::fprintf(stderr, "%s: the reference's own noise %.2f%%\n", name.c_str(), 100 * noise);
  for (const Traced& t : traced)
    std::printf("%s,path_tracer,%d,%.4e,%.4e\n", name.c_str(), t.spp, t.seconds,
                without_noise(t.error, noise));
  const double size = default_element_size(base);
  struct Setting {
    double element_scale, unshot;  // times the scene's
  };
  for (DirectLight direct : {DirectLight::Exact, DirectLight::Radiosity})
    for (Setting setting :
         {Setting{1, 3}, Setting{1, 1}, Setting{1, 0.3}, Setting{2, 0.3}, Setting{0.5, 0.3}}) {
      Scene s = base;
      s.solver.direct_light = direct;
      s.solver.element_size = size * setting.element_scale;
      s.solver.unshot_fraction = setting.unshot * base.solver.unshot_fraction;
      s.solver.max_shots = 20000;
      t0 = Clock::now();
      const Solution solution = solve(s);
      const Image image = render(s, solution);
      const double seconds = seconds_since(t0);
      std::printf("%s,%s,%zu,%.4e,%.4e\n", name.c_str(),
                  direct == DirectLight::Exact ? "exact" : "radiosity",
                  solution.mesh->elements.size(), seconds,
                  without_noise(compare(image, reference, emitter).surfaces, noise));
    }
}

}  // namespace
}  // namespace bumprad

int main(int argc, char** argv) {
  using namespace bumprad;
  std::vector<std::string> parts(argv + 1, argv + argc);
  // paper-room is left out of the default sweep: its 16,384-path reference alone takes
  // longer than the rest of the sweep (mirror and glossy paths).
  if (parts.empty()) parts = {"point", "perturbed", "cornell", "wrinkled-box"};
  try {
    std::printf("part,method,setting,seconds,error\n");
    for (const std::string& part : parts) {
      if (part == "point") {
        point_sweep("far", 1.0);
        point_sweep("near", 0.15);
      } else if (part == "perturbed") {
        perturbed_sweep();
      } else {
        image_sweep(part);
      }
      std::fflush(stdout);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bumprad-bench-accuracy: %s\n", e.what());
    return 1;
  }
}
