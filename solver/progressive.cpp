#include "solver/progressive.h"

#include <algorithm>
#include <chrono>
#include <numbers>

#include <glm/geometric.hpp>

namespace bumprad {
namespace {

double channel_sum(const Rgb& c) { return c.r + c.g + c.b; }

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
  hemicube_.render(origin, frame_about(patch.normal, angle), pi);

  // Element i receives power dB_j A_j F_ji and reflects rho_i of it:
  // dB_i += rho_i dB_j F_ji A_j / A_i.
  double seen = 0;
  for (const VisibleElement& v : hemicube_.form_factors()) {
    const Element& e = mesh_.elements[v.element];
    Rgb incident = shot_power * v.form_factor;
    Rgb reflected = reflectance_[v.element] * incident;
    Rgb dB = reflected / e.area;
    radiosity_[v.element] += dB;
    unshot_[v.element] += dB;
    patch_unshot_power_[e.patch] += channel_sum(reflected);
    absorbed_ += incident - reflected;
    seen += v.form_factor;
  }
  escaped_ += shot_power * std::max(0.0, 1.0 - seen);
  ++shots_;

  last_shot_ = {hemicube_.last_render_seconds(), hemicube_.last_accumulate_seconds(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
  total_.render_s += last_shot_.render_s;
  total_.accumulate_s += last_shot_.accumulate_s;
  total_.total_s += last_shot_.total_s;
  return true;
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
  for (std::size_t i = 0; i < unshot_.size(); ++i) unshot_mean += unshot_[i] * mesh_.elements[i].area;
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
