#include "solver/render/path_tracer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "solver/render/lights.h"
#include "solver/scene/bump.h"
#include "solver/scene/camera.h"
#include "solver/scene/geometry.h"
#include "solver/scene/phong_lobe.h"
#include "solver/scene/planar_mirror.h"
#include "solver/scene/texture.h"
#include "solver/util/frame.h"
#include "solver/util/parallel.h"
#include "solver/util/random.h"

namespace bumprad {
namespace {

class PathTracer {
 public:
  PathTracer(const Scene& scene, const Mesh& mesh, const RayScene& rays)
      : scene_(scene),
        mesh_(mesh),
        rays_(rays),
        lights_(mesh, scene.materials, scene.lights),
        planar_mirror_(planar_mirrors(mesh, scene.materials)),
        epsilon_(ray_epsilon(mesh)) {}

  // Radiance along the camera ray.
  Rgb radiance(Ray ray, Random& random) const {
    Rgb sum(0), throughput(1);
    // What the path met since it last left a diffuse surface. There next-event estimation
    // counted the emitters and their images in planar mirrors, so an emitter met straight
    // after it, or after one planar mirror, must not be counted again.
    // After a glossy surface next-event estimation counted the emitters and their images in
    // part (multiple importance sampling): an emitter met straight after it, or after one
    // planar mirror, counts with the lobe's weight.
    enum class Since {
      Camera,
      Diffuse,
      OneMirror,
      Glossy,
      GlossyMirror,
      Uncovered
    } since = Since::Camera;
    double lobe_pdf = 0, travelled = 0;  // since the last glossy surface: its density, length
    for (int depth = 0; depth < 1000; ++depth) {
      auto hit = rays_.intersect(ray);
      if (!hit || !hit->front) break;  // one-sided surfaces: a back face absorbs
      const Element& e = mesh_.elements[hit->element];
      const Material& m = scene_.materials[std::size_t(e.material)];
      const SurfaceAt s = surface_at(mesh_, e, hit->u, hit->v);
      if (since == Since::Camera || since == Since::Uncovered)
        sum += throughput * emission_at(m, s.uv) / kPi;
      else if ((since == Since::Glossy || since == Since::GlossyMirror) && m.emission != Rgb(0))
        sum += throughput * m.emission *
               (lights_.lobe_weight(lobe_pdf, hit->element, travelled + hit->t,
                                    -glm::dot(e.normal, ray.direction)) /
                kPi);

      Vec3 normal = s.normal;
      if (const int b = scene_.objects[e.object].bump; b >= 0)
        normal = bumped_normal(scene_.bumps[std::size_t(b)], s.uv, s.normal, s.dpdu, s.dpdv);
      const Vec3 point = ray.origin + hit->t * ray.direction;
      const Vec3 from = point + e.normal * epsilon_;
      const Rgb rho = m.texture ? texture_reflectance(*m.texture, s.uv) : m.reflectance;

      // Choose the diffuse or the specular part by their albedo; Russian roulette on what
      // is left. Each choice divides by its probability: unbiased.
      const double diffuse = std::max({rho.r, rho.g, rho.b});
      const double choice = random.next();
      if (choice < diffuse) {
        throughput *= rho / diffuse;
        sum += throughput * lights_.next_event(from, normal, rays_, random) / kPi;
        const Frame frame = frame_about(normal);
        const double r = std::sqrt(random.next()), phi = 2 * kPi * random.next();
        ray = {from, frame.to_world(Vec3(r * std::cos(phi), r * std::sin(phi),
                                         std::sqrt(std::max(0.0, 1 - r * r))))};
        since = Since::Diffuse;
      } else if (choice < diffuse + m.specular) {
        const Vec3 mirror = glm::reflect(ray.direction, normal);
        if (m.shininess > 0) {
          const PhongLobe lobe(mirror, normal, m.shininess);
          sum += throughput *
                 (lights_.glossy_punctual(from, e.normal, lobe, rays_) +
                  lights_.glossy_next_event(from, e.normal, lobe, rays_, random)) /
                 kPi;
          Vec3 d;
          if (!lobe.sample(random, d)) break;
          ray = {from, d};
          lobe_pdf = lobe.pdf(d);
          travelled = 0;
          since = Since::Glossy;
        } else {
          ray = {from, mirror};
          const bool planar = planar_mirror_[e.surface];
          travelled += hit->t;
          since = since == Since::Camera              ? Since::Camera
                  : since == Since::Diffuse && planar ? Since::OneMirror
                  : since == Since::Glossy && planar  ? Since::GlossyMirror
                                                      : Since::Uncovered;
        }
      } else {
        break;
      }
      if (glm::dot(ray.direction, e.normal) <= 0) break;  // into the element's own back
    }
    return sum;
  }

 private:
  const Scene& scene_;
  const Mesh& mesh_;
  const RayScene& rays_;
  Lights lights_;
  std::vector<bool> planar_mirror_;  // per surface
  double epsilon_;
};

// One pixel: the mean of `spp` paths through it, and the variance of that mean (channels
// summed). Seeded by the pixel's index, so a pixel is the same in every call.
struct PixelPaths {
  Rgb mean;
  double variance;
};
PixelPaths trace_pixel(const PathTracer& tracer, const PinholeCamera& pinhole, int width, int x,
                       int y, int spp, std::uint64_t seed) {
  Rgb sum(0), squares(0);
  for (int s = 0; s < spp; ++s) {
    const std::uint64_t index =
        (std::uint64_t(y) * std::uint64_t(width) + std::uint64_t(x)) * std::uint64_t(spp) +
        std::uint64_t(s);
    // Hashed: seeded index * 0x9e37... (the generator's own increment), path s + 1 replayed
    // path s's numbers shifted by one, and the paths of a pixel were far from independent.
    Random random(hash64(seed * 0x2545f4914f6cdd1dull + hash64(index)));
    const Rgb l = tracer.radiance(pinhole.ray(x + random.next(), y + random.next()), random);
    sum += l;
    squares += l * l;
  }
  const Rgb mean = sum / double(spp);
  const Rgb spread = glm::max(squares / double(spp) - mean * mean, Rgb(0));
  return {mean, (spread.r + spread.g + spread.b) / std::max(1.0, double(spp - 1))};
}

}  // namespace

Image render_reference(const Scene& scene, const Mesh& mesh, const RayScene& rays,
                       const ReferenceSettings& settings, const ReferenceProgress& progress,
                       std::stop_token stop) {
  const PathTracer tracer(scene, mesh, rays);
  const PinholeCamera pinhole(scene.camera);
  const int width = scene.camera.width, height = scene.camera.height;
  const int spp = std::max(1, settings.samples_per_pixel);
  Image image(width, height);
  std::atomic<int> rows_done{0};
  parallel_for(
      height,
      [&](int y) {
        for (int x = 0; x < width; ++x)
          image.set(x, y, trace_pixel(tracer, pinhole, width, x, y, spp, settings.seed).mean);
        const int done = ++rows_done;
        if (progress) progress(double(done) / height);
      },
      stop);
  return image;
}

std::vector<TracedPixel> trace_pixels(const Scene& scene, const Mesh& mesh, const RayScene& rays,
                                      std::span<const PixelIndex> pixels,
                                      const ReferenceSettings& settings) {
  const PathTracer tracer(scene, mesh, rays);
  const PinholeCamera pinhole(scene.camera);
  const int spp = std::max(1, settings.samples_per_pixel);
  std::vector<TracedPixel> out(pixels.size());
  parallel_for(int(pixels.size()), [&](int i) {
    const PixelIndex& p = pixels[std::size_t(i)];
    const PixelPaths t =
        trace_pixel(tracer, pinhole, scene.camera.width, p.x, p.y, spp, settings.seed);
    out[std::size_t(i)] = {p, t.mean, t.variance};
  });
  return out;
}

}  // namespace bumprad
