#include "solver/path_tracer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>

#include "solver/bump.h"
#include "solver/camera.h"
#include "solver/hemicube.h"
#include "solver/texture.h"
#include "solver/vertex_radiosity.h"

namespace bumprad {
namespace {

constexpr double kPi = std::numbers::pi;

// A counter-based generator (splitmix64) seeded per pixel and sample: the image does not
// depend on the number of threads or the order rows are taken in.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  double next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t state_;
};

// The emitting elements, to pick one in proportion to its emitted power (area times
// luminance of E) and a point on it uniformly.
class Lights {
 public:
  explicit Lights(const Mesh& mesh, const std::vector<Material>& materials) : mesh_(mesh) {
    double total = 0;
    for (std::uint32_t i = 0; i < mesh.elements.size(); ++i) {
      const Element& e = mesh.elements[i];
      const Rgb& emission = materials[std::size_t(e.material)].emission;
      double power = e.area * (emission.r + emission.g + emission.b);
      if (!(power > 0)) continue;
      total += power;
      elements_.push_back(i);
      cumulative_.push_back(total);
    }
    for (double& c : cumulative_) c /= total;
  }
  bool empty() const { return elements_.empty(); }

  struct Sample {
    std::uint32_t element;
    Vec3 point;
    double pdf_area;  // per unit area, over all lights
  };
  Sample sample(Random& random) const {
    const double pick = random.next();
    const std::size_t k = std::size_t(
        std::lower_bound(cumulative_.begin(), cumulative_.end(), pick) - cumulative_.begin());
    const std::size_t i = std::min(k, elements_.size() - 1);
    const Element& e = mesh_.elements[elements_[i]];
    const double chosen = cumulative_[i] - (i > 0 ? cumulative_[i - 1] : 0);
    auto corner = [&](int c) { return mesh_.vertices[e.v[std::size_t(c)]].position; };
    // A quad is two triangles (planar and convex); each is picked by its area.
    Vec3 a = corner(0), b = corner(1), c = corner(2);
    if (e.vertex_count == 4) {
      const double first =
          0.5 * glm::length(glm::cross(corner(1) - corner(0), corner(2) - corner(0)));
      if (random.next() * e.area >= first) b = corner(2), c = corner(3);
    }
    double s = std::sqrt(random.next()), t = random.next();
    Vec3 point = (1 - s) * a + s * (1 - t) * b + s * t * c;
    return {elements_[i], point, chosen / e.area};
  }

 private:
  const Mesh& mesh_;
  std::vector<std::uint32_t> elements_;
  std::vector<double> cumulative_;
};

class PathTracer {
 public:
  PathTracer(const Scene& scene, const Mesh& mesh, const RayScene& rays)
      : scene_(scene),
        mesh_(mesh),
        rays_(rays),
        lights_(mesh, scene.materials),
        epsilon_(ray_epsilon(mesh)) {}

  // Radiance along the camera ray.
  Rgb radiance(Ray ray, Random& random) const {
    Rgb sum(0), throughput(1);
    bool count_emission = true;  // no light was sampled for the previous bounce
    for (int depth = 0; depth < 1000; ++depth) {
      auto hit = rays_.intersect(ray);
      if (!hit || !hit->front) break;  // one-sided surfaces: a back face absorbs
      const Element& e = mesh_.elements[hit->element];
      const Material& m = scene_.materials[std::size_t(e.material)];
      if (count_emission) sum += throughput * m.emission / kPi;

      const SurfaceAt s = surface_at(mesh_, e, hit->u, hit->v);
      Vec3 normal = s.normal;
      if (const int b = scene_.objects[e.object].bump; b >= 0) {
        BumpSample f = evaluate_bump(scene_.bumps[std::size_t(b)], s.uv);
        normal = perturb_normal(s.normal, s.dpdu, s.dpdv, f.du, f.dv);
      }
      const Vec3 point = ray.origin + hit->t * ray.direction;
      const Vec3 from = point + e.normal * epsilon_;
      const Rgb rho = m.texture ? texture_reflectance(*m.texture, s.uv) : m.reflectance;

      // Choose the diffuse or the specular part by their albedo; Russian roulette on what
      // is left. Each choice divides by its probability: unbiased.
      const double diffuse = std::max({rho.r, rho.g, rho.b});
      const double choice = random.next();
      if (choice < diffuse) {
        throughput *= rho / diffuse;
        sum += throughput * direct_light(from, normal, random);
        const Frame frame = frame_about(normal);
        const double r = std::sqrt(random.next()), phi = 2 * kPi * random.next();
        ray = {from, frame.to_world(Vec3(r * std::cos(phi), r * std::sin(phi),
                                         std::sqrt(std::max(0.0, 1 - r * r))))};
        count_emission = false;
      } else if (choice < diffuse + m.specular) {
        const Vec3 mirror = glm::reflect(ray.direction, normal);
        Vec3 d = mirror;
        if (m.shininess > 0 && !phong_direction(mirror, normal, m.shininess, random, d)) break;
        ray = {from, d};
        count_emission = true;
      } else {
        break;
      }
      if (glm::dot(ray.direction, e.normal) <= 0) break;  // into the element's own back
    }
    return sum;
  }

 private:
  // Light from a point on an emitter, through a shadow ray (next-event estimation).
  Rgb direct_light(const Vec3& from, const Vec3& normal, Random& random) const {
    if (lights_.empty()) return Rgb(0);
    Lights::Sample light = lights_.sample(random);
    const Element& le = mesh_.elements[light.element];
    Vec3 d = light.point - from;
    const double distance2 = glm::dot(d, d);
    const double distance = std::sqrt(distance2);
    d /= distance;
    const double cos_here = glm::dot(normal, d), cos_there = -glm::dot(le.normal, d);
    if (cos_here <= 0 || cos_there <= 0) return Rgb(0);
    if (rays_.occluded({from, d}, distance - 2 * epsilon_)) return Rgb(0);
    // (rho / pi) (E / pi) cos cos' / (r^2 pdf); rho is in the throughput already.
    return scene_.materials[std::size_t(le.material)].emission / (kPi * kPi) * cos_here *
           cos_there / (distance2 * light.pdf_area);
  }

  // A direction from the Phong lobe about `mirror`, drawn again while it points below the
  // surface (the view pass renormalises the lobe the same way); false if none is found.
  static bool phong_direction(const Vec3& mirror, const Vec3& normal, double shininess,
                              Random& random, Vec3& out) {
    const Frame lobe = frame_about(mirror);
    for (int attempt = 0; attempt < 64; ++attempt) {
      const double cos_a = std::pow(random.next(), 1 / (shininess + 1));
      const double sin_a = std::sqrt(std::max(0.0, 1 - cos_a * cos_a));
      const double phi = 2 * kPi * random.next();
      out = lobe.to_world(Vec3(sin_a * std::cos(phi), sin_a * std::sin(phi), cos_a));
      if (glm::dot(out, normal) > 0) return true;
    }
    return false;
  }

  // Embree intersects in single precision: a ray must leave its surface by some ulps of
  // the scene's coordinates, or it meets the surface it left (from behind, absorbed: at
  // 1e-7 of the diagonal the Cornell box came out 1.3 % too dark). 4e-6 of the largest
  // coordinate is about 64 ulps, and 12 micrometres in wrinkled-box, whose rug lies 1 mm
  // above its floor.
  static double ray_epsilon(const Mesh& mesh) {
    double extent = 0;
    for (int k = 0; k < 3; ++k)
      extent = std::max({extent, std::abs(mesh.bounds_min[k]), std::abs(mesh.bounds_max[k])});
    return 4e-6 * extent;
  }

  const Scene& scene_;
  const Mesh& mesh_;
  const RayScene& rays_;
  Lights lights_;
  double epsilon_;
};

}  // namespace

Image render_reference(const Scene& scene, const Mesh& mesh, const RayScene& rays,
                       const ReferenceSettings& settings, const ReferenceProgress& progress,
                       std::stop_token stop) {
  const PathTracer tracer(scene, mesh, rays);
  const PinholeCamera pinhole(scene.camera);
  const int width = scene.camera.width, height = scene.camera.height;
  const int spp = std::max(1, settings.samples_per_pixel);
  Image image(width, height);
  std::atomic<int> next_row{0}, rows_done{0};
  auto work = [&] {
    for (int y; !stop.stop_requested() && (y = next_row++) < height;) {
      for (int x = 0; x < width; ++x) {
        Rgb sum(0);
        for (int s = 0; s < spp; ++s) {
          const std::uint64_t index =
              (std::uint64_t(y) * std::uint64_t(width) + std::uint64_t(x)) * std::uint64_t(spp) +
              std::uint64_t(s);
          Random random(settings.seed * 0x2545f4914f6cdd1dull + index * 0x9e3779b97f4a7c15ull);
          sum += tracer.radiance(pinhole.ray(x + random.next(), y + random.next()), random);
        }
        image.set(x, y, sum / double(spp));
      }
      const int done = ++rows_done;
      if (progress) progress(double(done) / height);
    }
  };
  unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::jthread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  return image;
}

}  // namespace bumprad
