#include "solver/progressive.h"

#include <algorithm>
#include <chrono>
#include <numbers>

#include <glm/geometric.hpp>

#include "solver/form_factor_exact.h"

namespace bumprad {
namespace {

double channel_sum(const Rgb& c) {
  return c.r + c.g + c.b;
}

// Receivers closer than this many shooter sizes (sqrt of the patch area) are near field.
constexpr double kNearField = 3.0;

// Four points per element spread over its area: the centres of its 2 x 2 bilinear
// sub-quads, or of a triangle's four midpoint sub-triangles.
void add_element_samples(const Mesh& mesh, const Element& e, double patch_area,
                         std::vector<Vec3>& points, std::vector<double>& weights) {
  auto p = [&](int k) { return mesh.vertices[e.v[k]].position; };
  if (e.vertex_count == 4) {
    for (double u : {0.25, 0.75})
      for (double v : {0.25, 0.75})
        points.push_back((1 - u) * (1 - v) * p(0) + u * (1 - v) * p(1) + u * v * p(2) +
                         (1 - u) * v * p(3));
  } else {
    Vec3 c = (p(0) + p(1) + p(2)) / 3.0;
    for (int k = 0; k < 3; ++k) points.push_back((2.0 * p(k) + c) / 3.0);
    points.push_back(c);
  }
  for (int k = 0; k < 4; ++k) weights.push_back(e.area / (4 * patch_area));
}

}  // namespace

ProgressiveSolver::ProgressiveSolver(const Mesh& mesh, const std::vector<Material>& materials,
                                     const SolverSettings& settings)
    : mesh_(mesh),
      settings_(settings),
      hemicube_(mesh, settings.hemicube_resolution),
      reflectance_(mesh.elements.size()),
      radiosity_(mesh.elements.size()),
      unshot_(mesh.elements.size()),
      patch_unshot_power_(mesh.patches.size(), 0.0),
      rng_(settings.seed) {
  samples_.resize(mesh.patches.size());
  for (std::size_t p = 0; p < mesh.patches.size(); ++p) {
    const Patch& patch = mesh.patches[p];
    std::vector<Vec3> points;
    std::vector<double> weights;
    for (std::uint32_t e = patch.first; e < patch.first + patch.count; ++e)
      add_element_samples(mesh, mesh.elements[e], patch.area, points, weights);
    for (std::size_t k = 0; k < points.size(); ++k) samples_[p].push_back({points[k], weights[k]});
  }
  Rgb weighted_rho(0);
  for (std::size_t i = 0; i < mesh.elements.size(); ++i) {
    const Element& e = mesh.elements[i];
    const Material& m = materials[std::size_t(e.material)];
    reflectance_[i] = m.reflectance;
    radiosity_[i] = unshot_[i] = m.emission;
    emitted_ += m.emission * e.area;
    patch_unshot_power_[e.patch] += channel_sum(m.emission) * e.area;
    weighted_rho += m.reflectance * e.area;
    total_area_ += e.area;
  }
  if (total_area_ > 0) ambient_factor_ = 1.0 / (1.0 - weighted_rho / total_area_);
}

double ProgressiveSolver::unshot_fraction() const {
  double emitted = channel_sum(emitted_);
  if (emitted <= 0) return 0;
  double unshot = 0;
  for (double p : patch_unshot_power_) unshot += p;
  return std::max(0.0, unshot) / emitted;
}

void ProgressiveSolver::attach_map(PerturbedMap* map) {
  map_ = map;
  hemicube_.watch(map ? map->perturbed_elements() : std::vector<bool>{});
}

bool ProgressiveSolver::done() const {
  return shots_ >= settings_.max_shots || unshot_fraction() <= settings_.unshot_fraction;
}

bool ProgressiveSolver::shoot() {
  auto t0 = std::chrono::steady_clock::now();
  auto best = std::max_element(patch_unshot_power_.begin(), patch_unshot_power_.end());
  if (best == patch_unshot_power_.end() || *best <= 0) return false;
  const std::uint32_t pi = std::uint32_t(best - patch_unshot_power_.begin());
  const Patch& patch = mesh_.patches[pi];

  // The patch shoots the area-weighted mean of its elements' unshot radiosity.
  Rgb shot_power(0);
  for (std::uint32_t e = patch.first; e < patch.first + patch.count; ++e) {
    shot_power += unshot_[e] * mesh_.elements[e].area;
    unshot_[e] = Rgb(0);
  }
  patch_unshot_power_[pi] = 0;

  double angle = 0;
  if (settings_.rotate_hemicube)
    angle = std::uniform_real_distribution<double>(0, 2 * std::numbers::pi)(rng_);
  Vec3 origin = patch.centroid + patch.normal * (mesh_.diagonal() * 1e-6);
  const Frame frame = frame_about(patch.normal, angle);
  hemicube_.render(origin, frame, pi);

  // Near-field corrections redistribute what the hemi-cube saw among the receivers; its
  // total (one minus the empty pixels) stays as rendered, so no energy is made or lost.
  auto& visible = hemicube_.form_factors();
  const double near = kNearField * std::sqrt(patch.area);
  double seen = 0, corrected = 0;
  for (VisibleElement& v : visible) {
    seen += v.form_factor;
    if (glm::length(mesh_.elements[v.element].centroid - patch.centroid) < near)
      v.form_factor = near_field_form_factor(pi, origin, v.element, v.form_factor);
    corrected += v.form_factor;
  }
  const double scale = corrected > 0 ? seen / corrected : 0;
  for (VisibleElement& v : visible) v.form_factor *= scale;

  // Element i receives power dB_j A_j F_ji and reflects rho_i of it:
  // dB_i += rho_i dB_j F_ji A_j / A_i.
  for (const VisibleElement& v : visible) {
    const Element& e = mesh_.elements[v.element];
    Rgb incident = shot_power * v.form_factor;
    Rgb reflected = reflectance_[v.element] * incident;
    Rgb dB = reflected / e.area;
    radiosity_[v.element] += dB;
    unshot_[v.element] += dB;
    patch_unshot_power_[e.patch] += channel_sum(reflected);
    absorbed_ += incident - reflected;
  }
  escaped_ += shot_power * std::max(0.0, 1.0 - seen);
  ++shots_;

  double texture_s = 0;
  if (map_) {
    auto t1 = std::chrono::steady_clock::now();
    map_->shoot(hemicube_, frame, shot_power, visible);
    texture_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  }
  last_shot_ = {hemicube_.last_render_seconds(), hemicube_.last_accumulate_seconds(), texture_s,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
  total_.render_s += last_shot_.render_s;
  total_.accumulate_s += last_shot_.accumulate_s;
  total_.texture_s += last_shot_.texture_s;
  total_.total_s += last_shot_.total_s;
  return true;
}

// Near field (DESIGN.md section 4; Baum, Rushmeier & Winget 1989): one hemi-cube at the
// patch centre misjudges receivers within a few patch sizes, by +20% for parallel unit
// squares one unit apart. Keep the hemi-cube's visible fraction of the receiver, but take
// its unoccluded form factor as the mean of the exact point-to-polygon values (Lambert)
// over points spread across the shooting patch.
double ProgressiveSolver::near_field_form_factor(std::uint32_t patch, const Vec3& origin,
                                                 std::uint32_t element,
                                                 double hemicube_form_factor) const {
  const Element& e = mesh_.elements[element];
  std::array<Vec3, 4> polygon;
  for (int k = 0; k < e.vertex_count; ++k) polygon[k] = mesh_.vertices[e.v[k]].position;
  std::span<const Vec3> receiver(polygon.data(), std::size_t(e.vertex_count));
  const Vec3& n = mesh_.patches[patch].normal;
  double at_origin = point_to_polygon(origin, n, receiver);
  if (!(at_origin > 0)) return hemicube_form_factor;
  double visible = std::min(1.0, hemicube_form_factor / at_origin);
  double mean = 0;
  for (const ShooterSample& s : samples_[patch])
    mean += s.weight * point_to_polygon(s.point, n, receiver);
  return visible * mean;
}

void ProgressiveSolver::run(const std::function<bool(const Snapshot&)>& on_step) {
  const int every = std::max(1, settings_.preview_every);
  while (!done()) {
    if (!shoot()) break;
    if (on_step && shots_ % every == 0 && !done() && !on_step(snapshot())) return;
  }
  if (on_step) on_step(snapshot());
}

std::vector<Rgb> ProgressiveSolver::display_radiosity() const {
  Rgb unshot_mean(0);
  for (std::size_t i = 0; i < unshot_.size(); ++i)
    unshot_mean += unshot_[i] * mesh_.elements[i].area;
  Rgb ambient = total_area_ > 0 ? ambient_factor_ * unshot_mean / total_area_ : Rgb(0);
  std::vector<Rgb> out(radiosity_.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = radiosity_[i] + reflectance_[i] * ambient;
  return out;
}

Snapshot ProgressiveSolver::snapshot() const {
  return {shots_, unshot_fraction(), done(), display_radiosity()};
}

EnergyLedger ProgressiveSolver::ledger() const {
  Rgb unshot(0);
  for (std::size_t i = 0; i < unshot_.size(); ++i) unshot += unshot_[i] * mesh_.elements[i].area;
  return {emitted_, absorbed_, escaped_, unshot};
}

}  // namespace bumprad
