// Scale benchmark: a family of generated scenes from 10k to 1M triangles, and per size the
// set-up (mesh, rays, open shares, near field), the shots, the solve, the view pass, the
// peak memory, the error against the path tracer, and the cost model's expected shots and
// the measured time over its estimate (solver/cost.h); then a fit of time against
// triangles, t ~ N^a.
//   build/bin/bumprad-bench-scale [--family room|terrain|objects|models] [--sizes 10000,100000]
//                                 [--spp N] [--references DIR] [--width W]
// Families: `room`, a room whose floor is a smooth, gently rolling triangle mesh with three
// tessellated boxes standing on it, lit by two ceiling panels; `terrain`, hills under one
// wide panel; `objects`, a room with a grid of small tessellated spheres on its floor;
// `models`, four copies of an imported model (the Wuson figure of assimp-testmodels, 3,732
// triangles a copy) on a room's floor, each triangle cut in m x m for the size. Each
// size runs in a child process, so that its peak resident memory is its own. References are
// path-traced at --spp (default 1024) and kept in --references (default
// bench-references/) as FAMILY-N-WIDTH-SPP-SEED.exr, so a second run reuses them; their own
// noise is taken out of the error as bumprad-bench-truth does (from a second render at
// spp / 4). bumprad's own image is written beside them, FAMILY-N-WIDTH-bumprad.exr, to see
// where the error lies.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "bench/truth_metrics.h"
#include "common/args.h"
#include "common/stopwatch.h"
#include "protocol/model_import.h"
#include "solver/cost.h"
#include "solver/render/path_tracer.h"
#include "solver/scene/mesh.h"
#include "solver/scene/ray_scene.h"
#include "solver/solution.h"
#include "solver/util/image.h"

namespace {

using namespace bumprad;

constexpr const char* kUsage =
    "usage: bumprad-bench-scale [--family room|terrain|objects|models] [--sizes N,N,...] "
    "[--spp N] [--references DIR] [--width W]\n";
// The `models` family's model (Debian's assimp-testmodels, which scripts/setup.sh --tests
// installs).
constexpr const char* kModel = "/usr/share/assimp/models/OBJ/WusonOBJ.obj";

// An nu x nv grid of triangle pairs over p(u, v), u and v in [0, 1], facing dp/dv x dp/du.
template <typename F>
TriangleMeshShape grid_mesh(int nu, int nv, F p) {
  TriangleMeshShape m;
  m.smooth = true;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) m.positions.push_back(p(double(i) / nu, double(j) / nv));
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const std::uint32_t a = std::uint32_t(j * (nu + 1) + i), b = a + 1,
                          c = a + std::uint32_t(nu + 1), d = c + 1;
      m.triangles.push_back({a, c, b});  // counter-clockwise seen along dp/dv x dp/du
      m.triangles.push_back({b, c, d});
    }
  return m;
}

// A closed box as six grids of n x n quads (two triangles each), faces out; not smooth, so
// its edges stay creases.
TriangleMeshShape box_mesh(const Vec3& centre, double size, double turn, int n) {
  TriangleMeshShape m;
  const double c = std::cos(turn), s = std::sin(turn);
  auto place = [&](Vec3 q) {
    q *= size / 2;
    return centre + Vec3(c * q.x + s * q.z, q.y, -s * q.x + c * q.z);
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = -1; side <= 1; side += 2) {
      Vec3 normal(0), e1(0), e2(0);
      normal[axis] = side;
      e1[(axis + 1) % 3] = 1;
      e2[(axis + 2) % 3] = -side;  // e2 x e1 along the normal
      TriangleMeshShape face = grid_mesh(n, n, [&](double u, double v) {
        return place(normal + (2 * u - 1) * e1 + (2 * v - 1) * e2);
      });
      const std::uint32_t base = std::uint32_t(m.positions.size());
      m.positions.insert(m.positions.end(), face.positions.begin(), face.positions.end());
      for (auto t : face.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
  return m;
}

// A smooth latitude-longitude sphere of about `triangles` triangles.
TriangleMeshShape sphere_mesh(const Vec3& centre, double radius, int triangles) {
  const int rings = std::max(3, int(std::sqrt(triangles / 4.0)));
  return grid_mesh(2 * rings, rings, [&](double u, double v) {
    const double phi = 2 * kPi * u, theta = kPi * (1 - v);
    if (v == 0 || v == 1) return centre + Vec3(0, radius * std::cos(theta), 0);  // weld poles
    return centre + radius * Vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                  std::sin(theta) * std::sin(phi));
  });
}

// Each triangle cut into m x m on the grid of its edges' m-ths, its per-position attributes
// interpolated (normals renormalised): the same surface in m^2 times the triangles. A point
// on an edge comes out the same from both of its triangles (the weights' terms commute), so
// the mesh's welding joins them.
TriangleMeshShape cut_triangles(const TriangleMeshShape& in, int m) {
  if (m <= 1) return in;
  TriangleMeshShape out;
  out.smooth = in.smooth;
  for (const auto& t : in.triangles) {
    const std::uint32_t base = std::uint32_t(out.positions.size());
    auto index = [&](int i, int j) {  // i steps from t[0] to t[1], j from t[0] to t[2]
      return base + std::uint32_t(j * (m + 1) - j * (j - 1) / 2 + i);
    };
    for (int j = 0; j <= m; ++j)
      for (int i = 0; i + j <= m; ++i) {
        const double w1 = double(i) / m, w2 = double(j) / m, w0 = double(m - i - j) / m;
        auto mix = [&](const auto& values) {
          return w0 * values[t[0]] + w1 * values[t[1]] + w2 * values[t[2]];
        };
        out.positions.push_back(mix(in.positions));
        if (!in.uvs.empty()) out.uvs.push_back(mix(in.uvs));
        if (!in.normals.empty()) out.normals.push_back(glm::normalize(mix(in.normals)));
        if (!in.tangents.empty()) {
          glm::dvec4 tangent = mix(in.tangents);
          tangent.w = in.tangents[t[0]].w;
          out.tangents.push_back(tangent);
        }
      }
    for (int j = 0; j < m; ++j)
      for (int i = 0; i + j < m; ++i) {
        out.triangles.push_back({index(i, j), index(i + 1, j), index(i, j + 1)});
        if (i + j + 1 < m)
          out.triangles.push_back({index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)});
      }
  }
  return out;
}

std::size_t triangle_count(const Scene& scene) {
  std::size_t n = 0;
  for (const Object& o : scene.objects)
    if (const auto* m = std::get_if<TriangleMeshShape>(&o.shape)) n += m->triangles.size();
  return n;
}

// A W x H x D room of quads (seen from inside) with the given ceiling panels, white walls
// but one red and one green.
Scene room(double w, double h, double d, const std::vector<std::array<double, 4>>& panels) {
  Scene scene;
  auto make = [](const char* name, Rgb reflectance, Rgb emission) {
    Material m;
    m.name = name;
    m.reflectance = reflectance;
    m.emission = emission;
    return m;
  };
  scene.materials = {make("white", Rgb(0.7), Rgb(0)), make("red", Rgb(0.6, 0.1, 0.1), Rgb(0)),
                     make("green", Rgb(0.1, 0.6, 0.1), Rgb(0)), make("light", Rgb(0.7), Rgb(20))};
  auto quad = [&](const char* name, int material, Vec3 a, Vec3 b, Vec3 c, Vec3 e) {
    Object o;
    o.name = name;
    o.material = material;
    o.shape = QuadShape{{a, b, c, e}};
    scene.objects.push_back(std::move(o));
  };
  quad("ceiling", 0, {0, h, 0}, {w, h, 0}, {w, h, d}, {0, h, d});
  quad("back", 0, {0, h, d}, {w, h, d}, {w, 0, d}, {0, 0, d});
  quad("front", 0, {0, 0, 0}, {w, 0, 0}, {w, h, 0}, {0, h, 0});
  quad("left", 1, {0, h, 0}, {0, h, d}, {0, 0, d}, {0, 0, 0});
  quad("right", 2, {w, 0, 0}, {w, 0, d}, {w, h, d}, {w, h, 0});
  for (const auto& [x0, z0, x1, z1] : panels)
    quad("panel", 3, {x0, h - 0.01, z0}, {x1, h - 0.01, z0}, {x1, h - 0.01, z1},
         {x0, h - 0.01, z1});
  scene.camera.position = {w / 2, 0.5 * h, 0.05 * d};
  scene.camera.look_at = {w / 2, 0.2 * h, 0.75 * d};
  scene.camera.fov_y_deg = 75;
  scene.camera.width = scene.camera.height = 256;
  return scene;
}

// A 4 x 3 x 4 m room under a 1 m ceiling panel, with a floor quad for things to stand on.
Scene room_with_floor() {
  Scene scene = room(4, 3, 4, {{1.5, 1.5, 2.5, 2.5}});
  Object floor;
  floor.name = "floor";
  floor.shape = QuadShape{{Vec3(0, 0, 0), Vec3(0, 0, 4), Vec3(4, 0, 4), Vec3(4, 0, 0)}};
  scene.objects.push_back(std::move(floor));
  return scene;
}

void add_mesh(Scene& scene, const std::string& name, TriangleMeshShape mesh) {
  Object o;
  o.name = name;
  o.shape = std::move(mesh);
  scene.objects.push_back(std::move(o));
}

// The family's scene with about `triangles` triangles.
Scene make_scene(const std::string& family, std::size_t triangles) {
  const double n = double(triangles);
  if (family == "room") {
    Scene scene = room(4, 3, 4, {{1, 1, 1.6, 1.6}, {2.4, 2.4, 3, 3}});
    // Three quarters of the triangles on the floor, the rest on the boxes' 18 faces.
    const int floor = std::max(1, int(std::sqrt(0.75 * n / 2)));
    const int faces = std::max(1, int(std::sqrt(0.25 * n / 36)));
    add_mesh(scene, "floor", grid_mesh(floor, floor, [](double u, double v) {
               const double x = 4 * u, z = 4 * v;
               return Vec3(x, 0.02 * std::sin(3 * x) * std::cos(2 * z), z);
             }));
    add_mesh(scene, "box 1", box_mesh({1, 0.33, 3}, 0.6, 0, faces));
    add_mesh(scene, "box 2", box_mesh({3, 0.43, 1.2}, 0.8, 0.35, faces));
    add_mesh(scene, "box 3", box_mesh({2, 0.28, 2.2}, 0.5, 0.7, faces));
    return scene;
  }
  if (family == "terrain") {
    Scene scene = room(10, 5, 10, {{3, 3, 7, 7}});
    const int side = std::max(1, int(std::sqrt(n / 2)));
    add_mesh(scene, "terrain", grid_mesh(side, side, [](double u, double v) {
               const double x = 10 * u, z = 10 * v;
               const double hills =
                   0.8 * std::sin(0.9 * x) * std::sin(0.7 * z) + 0.3 * std::cos(2.1 * x + 1.3 * z);
               return Vec3(
                   x, 1.1 + hills * (1 - std::pow(2 * u - 1, 8)) * (1 - std::pow(2 * v - 1, 8)), z);
             }));
    scene.camera.position = {5, 3.8, 0.3};
    scene.camera.look_at = {5, 1, 6};
    return scene;
  }
  if (family == "objects") {
    // 10 x 10 spheres on a floor quad share the triangles alike.
    Scene scene = room_with_floor();
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j) {
        const double r = 0.08 + 0.04 * ((i * 7 + j * 3) % 5) / 4.0;
        add_mesh(scene, "sphere " + std::to_string(10 * i + j),
                 sphere_mesh({0.3 + 0.38 * i, r, 0.3 + 0.38 * j}, r, int(n / 100)));
      }
    return scene;
  }
  if (family == "models") {
    // Four copies of an imported model on a floor, each triangle cut into m x m to reach the
    // size: the same scene at every size, as the other families are.
    Scene scene = room_with_floor();
    ImportedModel model = import_model(kModel);
    Vec3 lo(INFINITY), hi(-INFINITY);
    std::size_t per_copy = 0;
    for (const Object& o : model.objects)
      if (const auto* m = std::get_if<TriangleMeshShape>(&o.shape)) {
        per_copy += m->triangles.size();
        for (const Vec3& p : m->positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
      }
    const int copies = 4, side = 2;
    const int cuts = std::max(1, int(std::lround(std::sqrt(n / double(copies * per_copy)))));
    for (Object& o : model.objects)
      if (auto* m = std::get_if<TriangleMeshShape>(&o.shape)) *m = cut_triangles(*m, cuts);
    const double cell = 3.6 / side, scale = 0.7 * cell / std::max(hi.x - lo.x, hi.z - lo.z);
    const int first_material = int(scene.materials.size());
    scene.materials.insert(scene.materials.end(), model.materials.begin(), model.materials.end());
    for (int c = 0; c < copies; ++c) {
      ImportedModel copy = model;
      const Vec3 at(0.2 + cell * (c % side + 0.5), 0, 0.2 + cell * (c / side + 0.5));
      transform_model(
          copy,
          glm::translate(glm::dmat4(1), at) * glm::scale(glm::dmat4(1), Vec3(scale)) *
              glm::translate(glm::dmat4(1), -Vec3((lo.x + hi.x) / 2, lo.y, (lo.z + hi.z) / 2)));
      for (Object& o : copy.objects) {
        o.material += first_material;
        o.bump = -1;
        scene.objects.push_back(std::move(o));
      }
    }
    return scene;
  }
  throw std::invalid_argument("--family: \"" + family +
                              "\" is not room, terrain, objects or models");
}

struct Result {
  std::size_t triangles = 0, elements = 0;
  int shots = 0;
  double setup = 0, solve = 0, view = 0, unshot = 0, error = 0, noise = 0;
  double estimated_shots = 0, estimated_s = 0;  // solver/cost.h, before the solve
  long peak_kb = 0;
};

// One size, in this (child) process: the figures as a line of numbers on `out`.
void measure(const std::string& family, std::size_t size, int spp, int width,
             const std::filesystem::path& references, FILE* out) {
  Scene scene = make_scene(family, size);
  if (width > 0) scene.camera.width = scene.camera.height = width;
  Result r;
  r.triangles = triangle_count(scene);
  const CostEstimate cost = estimate_cost(scene);
  r.estimated_shots = cost.shots;
  r.estimated_s = cost.solve_s + cost.render_s;
  auto t = Clock::now();
  const Solution solution = solve(scene);
  const double wall = seconds_since(t);
  t = Clock::now();
  const Image image = render(scene, solution);
  r.view = seconds_since(t);
  r.elements = solution.stats.elements;
  r.shots = solution.stats.shots;
  r.setup = solution.stats.seconds_setup;
  r.solve = wall - r.setup;
  r.unshot = solution.stats.unshot_fraction;
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  r.peak_kb = usage.ru_maxrss;  // before the references, which build their own mesh

  // The reference and a quarter-spp render at another seed, for its noise (noise_quarter =
  // 2 noise_ref, independent: their difference is sqrt(5) noise_ref).
  const Mesh mesh = build_mesh(scene);
  const RayScene rays(mesh);
  std::filesystem::create_directories(references);
  const std::string stem = family + "-" + std::to_string(size) + "-" + std::to_string(width) + "-";
  write_image((references / (stem + "bumprad.exr")).string(), image, 1);
  auto cached = [&](int samples, std::uint32_t seed) {
    const std::filesystem::path path =
        references / (stem + std::to_string(samples) + "-" + std::to_string(seed) + ".exr");
    if (std::filesystem::exists(path)) return read_image(path.string());
    Image im = render_reference(scene, mesh, rays, {samples, seed});
    write_image(path.string(), im, 1);
    return im;
  };
  const Image reference = cached(spp, 1), quarter = cached(std::max(1, spp / 4), 2);
  const std::vector<bool> emitter = emitter_pixels(scene, mesh, rays);
  r.noise = compare(quarter, reference, emitter).surfaces / std::sqrt(5.0);
  r.error = without_noise(compare(image, reference, emitter).surfaces, r.noise);
  std::fprintf(out, "%zu %zu %d %.17g %.17g %.17g %.17g %.17g %.17g %ld %.17g %.17g\n", r.triangles,
               r.elements, r.shots, r.setup, r.solve, r.view, r.unshot, r.error, r.noise, r.peak_kb,
               r.estimated_shots, r.estimated_s);
}

// Runs measure() in a child and reads its line back.
bool run_child(const std::string& family, std::size_t size, int spp, int width,
               const std::filesystem::path& references, Result& r) {
  int fd[2];
  if (pipe(fd) != 0) return false;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    FILE* out = fdopen(fd[1], "w");
    try {
      measure(family, size, spp, width, references, out);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bumprad-bench-scale: %zu triangles: %s\n", size, e.what());
      _exit(1);
    }
    std::fclose(out);
    _exit(0);
  }
  close(fd[1]);
  FILE* in = fdopen(fd[0], "r");
  const int n = std::fscanf(in, "%zu %zu %d %lf %lf %lf %lf %lf %lf %ld %lf %lf", &r.triangles,
                            &r.elements, &r.shots, &r.setup, &r.solve, &r.view, &r.unshot, &r.error,
                            &r.noise, &r.peak_kb, &r.estimated_shots, &r.estimated_s);
  std::fclose(in);
  int status = 0;
  waitpid(pid, &status, 0);
  return n == 12 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string family = "room", sizes_text = "10000,30000,100000,300000,1000000",
              references = "bench-references";
  int spp = 1024, width = 256;
  ArgParser()
      .text({"--family"}, family)
      .text({"--sizes"}, sizes_text)
      .integer({"--spp"}, spp, 4, 1 << 20)
      .text({"--references"}, references)
      .integer({"--width"}, width, 16, 4096)
      .parse_or_exit(argc, argv, kUsage);
  std::vector<std::size_t> sizes;
  std::stringstream list(sizes_text);
  for (std::string item; std::getline(list, item, ',');) {
    const long long n = std::atoll(item.c_str());
    if (n < 2) {
      std::fprintf(stderr, "bumprad-bench-scale: --sizes: \"%s\" is not a triangle count\n%s",
                   item.c_str(), kUsage);
      return 2;
    }
    sizes.push_back(std::size_t(n));
  }
  try {
    make_scene(family, 2);  // refuses an unknown family before any child starts
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bumprad-bench-scale: %s\n%s", e.what(), kUsage);
    return 2;
  }
  std::printf("family %s, %d x %d, reference %d samples a pixel\n", family.c_str(), width, width,
              spp);
  std::printf("%10s %10s %6s %8s %8s %8s %8s %8s %10s %9s %9s %8s\n", "triangles", "elements",
              "shots", "set-up s", "solve s", "view s", "unshot", "error", "ref noise", "peak MB",
              "est shots", "meas/est");
  std::vector<Result> results;
  for (std::size_t size : sizes) {
    Result r;
    if (!run_child(family, size, spp, width, references, r)) return 1;
    std::printf("%10zu %10zu %6d %8.2f %8.2f %8.2f %7.2f%% %7.2f%% %9.2f%% %9.0f %9.0f %8.2f\n",
                r.triangles, r.elements, r.shots, r.setup, r.solve, r.view, 100 * r.unshot,
                100 * r.error, 100 * r.noise, double(r.peak_kb) / 1024, r.estimated_shots,
                (r.setup + r.solve + r.view) / r.estimated_s);
    std::fflush(stdout);
    results.push_back(r);
  }
  // Least squares of log(set-up + solve + view) against log(triangles).
  if (results.size() >= 2) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const Result& r : results) {
      const double x = std::log(double(r.triangles)), y = std::log(r.setup + r.solve + r.view);
      sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    const double k = double(results.size());
    std::printf("time (set-up + solve + view) ~ triangles^%.2f\n",
                (k * sxy - sx * sy) / (k * sxx - sx * sx));
  }
  return 0;
}
