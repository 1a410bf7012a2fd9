// The scene's light sources: its emitting elements. The path tracer picks one by power and
// a point on it (next-event estimation); the view pass asks for the exact direct light at a
// point: Lambert's closed form per emitter, times the share of it shadow rays find visible,
// and the same for each emitter's virtual image in every planar mirror (Wallace, Cohen &
// Greenberg 1987), so light reflected once by a flat mirror is as exact as direct light.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/geometric.hpp>

#include "solver/scene/geometry.h"
#include "solver/scene/mesh.h"
#include "solver/scene/phong_lobe.h"
#include "solver/scene/planar_mirror.h"
#include "solver/scene/punctual_light.h"
#include "solver/scene/ray_scene.h"
#include "solver/scene/scene.h"
#include "solver/util/random.h"

namespace bumprad {

// The direct light at one point for any shading normal N (a bump's N'), from what its shadow
// rays found, which no normal changes: the sum over the sources seen of (k_s) E V F(N). While
// N's plane leaves every source wholly in front, each F(N) is N . polygon_vector() and the
// sum one linear map of N: at() applies it where covers() holds. Single precision: the view
// pass keeps one for every bumpy sample of an image.
struct DirectForm {
  std::array<glm::vec3, 3> rows{glm::vec3(0), glm::vec3(0), glm::vec3(0)};  // R, G, B
  // Every direction to a source lies in the cone about `axis` whose half-angle has sine
  // `reach`: N covers them all when N . axis > reach (2: a cone too wide for any N).
  glm::vec3 axis{0, 0, 1};
  float reach = -2;  // nothing seen: any N
  bool covers(const Vec3& n) const { return glm::dot(glm::vec3(n), axis) > reach; }
  Rgb at(const Vec3& n) const {
    const glm::vec3 f(n);
    return Rgb(glm::dot(rows[0], f), glm::dot(rows[1], f), glm::dot(rows[2], f));
  }
};

// The shadow rays of one hit (Lights::direct()) where it lies in a penumbra: 4 x `count` of
// them, to points of each source taken from a (0,2)-sequence shifted by `scramble` (a point
// that probes tell sees every source whole, or none, casts no more). The hits of one pixel
// share its scramble and each takes its own block of the sequence (this is hit `hit`), so
// that together they stratify a source as one net: over a penumbra a pixel then averages its
// rays as well spread as that many can be, where a shift of each hit's own would leave a net
// a hit, and twice the noise. The view pass and the map's vertices use one scramble
// everywhere, so that neighbours differ as the light does rather than as their points do.
struct ShadowRays {
  int count = 4;
  std::uint64_t scramble = 0;
  std::uint32_t hit = 0;
};

class Lights {
 public:
  Lights(const Mesh& mesh, std::span<const Material> materials,
         std::span<const PunctualLight> punctual = {});
  bool empty() const { return emitters_.empty() && punctual_.empty(); }

  struct Sample {
    std::uint32_t element;
    Vec3 point;
    double pdf_area;  // per unit area, over all lights
    Rgb emission;
  };
  // An emitter chosen by its power (area times E's channel sum), a point on it uniformly.
  Sample sample(Random& random) const;

  // The direct irradiance at `x` for shading normal `normal` (maybe a perturbed N') from the
  // punctual lights and their images in planar mirrors (punctual_sources(): exact, one
  // shadow ray each) and the emitters' own emission, in radiosity
  // units (sum over emitters l of E_l F(x -> l) V_l, W/m^2, before the receiver's
  // reflectance), plus k_s E_l F(x -> image of l) V for each planar mirror. F is exact
  // (Lambert, clipped to the plane of `normal`); V, the visible share (through the mirror,
  // for an image), comes from `shadow` rays spread over the emitters and images by their
  // contribution to the geometric surface (`geometric`, the element's own normal: light below
  // it is hidden, and the rays leave along it), to stratified points of them (a scrambled
  // (0,2)-sequence over their elements by area). Rays to each emitter surface's corners and
  // centre first tell whether the point sees it whole or not at all: it then gets the exact
  // value without noise, and only penumbrae cast the stratified rays. No ray depends on
  // `normal`: a bump changes F alone.
  Rgb direct(const Vec3& x, const Vec3& normal, const Vec3& geometric, const RayScene& rays,
             const ShadowRays& shadow) const;
  // The same rays' verdict kept for any normal to come (DirectForm): direct() and
  // direct_form().at() agree for every normal the form covers.
  DirectForm direct_form(const Vec3& x, const Vec3& geometric, const RayScene& rays,
                         const ShadowRays& shadow) const;
  // What direct_form() sums, source by source, from the same rays: each punctual light's
  // (or its image's) irradiance and unit direction (`polygon` empty), and each emitter or
  // mirror image seen, its E V (k_s V for an image) and polygon, whose clipped form factor
  // at N' is its F.
  using SourceVisitor =
      std::function<void(const Rgb& weight, const Vec3& toward, std::span<const Vec3> polygon)>;
  void direct_sources(const Vec3& x, const Vec3& geometric, const RayScene& rays,
                      const ShadowRays& shadow, const SourceVisitor& visit) const;

  // Next-event estimation for the path tracer, unbiased: each punctual light's irradiance
  // and its images' (deterministic), plus a point y on an emitter chosen by
  // power, E cos cos' / (pi r^2 pdf) if y is visible from `from`, plus the same through each
  // planar mirror (k_s times, to y's image): radiosity units, before the receiver's
  // reflectance. A path that leaves a diffuse surface and meets an emitter next, or after
  // one planar mirror, must then not count that emitter's emission again.
  Rgb next_event(const Vec3& from, const Vec3& normal, const RayScene& rays, Random& random) const;

  // Glossy highlights, with multiple importance sampling (Veach 1997, power heuristic) of
  // two strategies for the integral of E(d) lobe.pdf(d) over directions d (radiosity units,
  // before k_s): one emitter point chosen by power, seen straight and in each planar mirror
  // (this call: E lobe.pdf w / pdf per term, k_s times for an image, if visible from
  // `from`), and the caller's lobe direction, whose emission counts lobe_weight() times
  // when it meets an emitter straight or after one planar mirror. A small bright emitter in
  // a wide lobe is then found by the first, a sharp lobe by the second, without the
  // fireflies of either alone.
  Rgb glossy_next_event(const Vec3& from, const Vec3& geometric, const PhongLobe& lobe,
                        const RayScene& rays, Random& random) const;
  // The punctual lights' highlights, straight and in planar mirrors, in the same units: pi I
  // lobe.pdf(d) / r^2 for a point (d toward it, times a spot's cone), pi E lobe.pdf(d) for a
  // directional light, if visible from `from`. No lobe ray ever meets a point, so this is the
  // whole of their share, and deterministic.
  Rgb glossy_punctual(const Vec3& from, const Vec3& geometric, const PhongLobe& lobe,
                      const RayScene& rays) const;
  // The weight of a lobe direction (drawn with density `lobe_pdf`) that met emitter element
  // `element` after `distance` (through a planar mirror: the unfolded length), arriving at
  // cosine `cos_there` to the emitter's normal.
  double lobe_weight(double lobe_pdf, std::uint32_t element, double distance,
                     double cos_there) const;
  bool planar_mirror(std::uint32_t surface) const;

 private:
  Rgb punctual_direct(const Vec3& x, const Vec3& normal, const Vec3& from,
                      const RayScene& rays) const;
  Rgb area_next_event(const Vec3& from, const Vec3& normal, const RayScene& rays,
                      Random& random) const;
  struct Emitter {
    std::uint32_t element;
    Rgb emission;
    double weight;  // channel sum of E
  };
  // The emitter elements of one patch with one emission in one plane, for direct(): from afar
  // Lambert's form factor to their outline is the sum of theirs (one polygon where a lamp of
  // 2 x 2 elements took four), and a shadow ray picks one of them by area.
  struct Group {
    std::vector<Vec3> outline;
    std::vector<std::uint32_t> elements;
    std::vector<double> cumulative;  // by area, normalised
    Rgb emission;
    double weight;  // channel sum of E
    Vec3 point, normal;
    Vec3 centre;               // of area
    double radius;             // the farthest outline corner from the centre
    std::uint32_t probes = 0;  // its probe set (make_probe_sets())
  };
  // An emitter group, or one of its elements, or either's image in a mirror, as a point sees
  // it for direct().
  struct Seen {
    std::span<const std::uint32_t> elements;
    std::span<const double> cumulative;
    const Group* group;
    const PlanarMirror* mirror;  // null: the emitter itself
    double form_factor;
    double share;  // k_s E F, channel sum: how many rays it gets
  };
  double seen_from(const Vec3& x, const Vec3& normal, std::vector<Seen>& seen) const;
  void make_probe_sets();
  void add_probe_set(std::span<const std::size_t> members, std::span<const Vec3> corners);
  // 1 where shadow rays from `from` to the points of s's group's probe set (to their images
  // in s's mirror) all arrive, 0 where none does, -1 where they disagree: a penumbra.
  int probe(const Seen& s, const Vec3& from, const Vec3& geometric, const RayScene& rays) const;
  // A source seen and the share of it that shadow rays found visible (> 0).
  struct Visible {
    Seen seen;
    double share;
  };
  // The sources seen from x's geometric plane that its shadow rays reach (direct()).
  void visible(const Vec3& x, const Vec3& from, const Vec3& geometric, const RayScene& rays,
               const ShadowRays& shadow, std::vector<Visible>& out) const;
  // The polygon of what `s` sees, reflected in its mirror for an image.
  std::span<const Vec3> polygon(const Seen& s, std::vector<Vec3>& storage) const;
  Vec3 point_on(const Seen& s, double u, double v) const;
  bool arrives(const Seen& s, const Vec3& from, const Vec3& geometric, const Vec3& y,
               const RayScene& rays) const;
  void group_emitters();
  // The outline of coplanar elements that make one simple region (corners only), or empty.
  std::vector<Vec3> planar_outline(std::span<const std::uint32_t> elements) const;
  // The point (u, v) in [0,1)^2 of element e, uniform by area for uniform (u, v).
  Vec3 point_on(const Element& e, double u, double v) const;
  // Density per solid angle of sample() choosing a point on emitter element `element`
  // (0 for no emitter) seen at `distance` and cosine `cos_there` to its normal.
  double pdf_solid_angle(std::uint32_t element, double distance, double cos_there) const;
  // Whether `from` sees the point `to_image` (an emitter point's image) in `mirror`.
  bool visible_through(const PlanarMirror& mirror, const Vec3& from, const Vec3& to_image,
                       const RayScene& rays) const;

  const Mesh& mesh_;
  std::vector<PlanarMirror> mirrors_;
  std::vector<PunctualSource> punctual_;  // the lights and their images in mirrors_
  std::vector<Emitter> emitters_;
  std::vector<Group> groups_;
  std::vector<std::vector<Vec3>> probe_sets_;  // each: a centre, then corners
  std::vector<double> cumulative_;             // by power, normalised
  double total_power_ = 0;                     // sum of area times E's channel sum
  double epsilon_;
};

}  // namespace bumprad
