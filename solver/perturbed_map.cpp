#include "solver/perturbed_map.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "solver/vertex_radiosity.h"

namespace bumprad {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

// Shooting divides by the receiver's cosine toward the shooter (eq. 20). A grazing pixel
// would make that ratio blow up on aliasing noise; below this cosine (about 3 degrees
// above the surface) the divisor is held, which bounds the ratio by 1 / kMinCosine.
constexpr double kMinCosine = 0.05;

}  // namespace

DirectionSet::DirectionSet(const MapSettings& settings) : azimuths_(settings.azimuths) {
  for (double t : settings.tilts_deg) tilts_.push_back(t * std::numbers::pi / 180);
  std::sort(tilts_.begin(), tilts_.end());
  directions_.push_back(Vec3(0, 0, 1));
  for (double tilt : tilts_)
    for (int k = 0; k < azimuths_; ++k) {
      double phi = kTwoPi * k / azimuths_;
      directions_.push_back(
          Vec3(std::sin(tilt) * std::cos(phi), std::sin(tilt) * std::sin(phi), std::cos(tilt)));
    }
}

int DirectionSet::weights(const Vec3& local, std::array<Weight, 4>& out) const {
  if (tilts_.empty()) {
    out[0] = {0, 1};
    return 1;
  }
  double theta = std::acos(std::clamp(local.z / glm::length(local), -1.0, 1.0));
  double a = std::atan2(local.y, local.x) / kTwoPi * azimuths_;
  if (a < 0) a += azimuths_;
  int k0 = std::min(int(a), azimuths_ - 1), k1 = (k0 + 1) % azimuths_;
  double t = a - k0;
  auto ring = [&](std::size_t r, double w, int at) {
    std::uint32_t base = std::uint32_t(1 + r * std::size_t(azimuths_));
    out[at] = {base + std::uint32_t(k0), w * (1 - t)};
    out[at + 1] = {base + std::uint32_t(k1), w * t};
  };
  if (theta >= tilts_.back()) {
    ring(tilts_.size() - 1, 1, 0);
    return 2;
  }
  std::size_t r =
      std::size_t(std::upper_bound(tilts_.begin(), tilts_.end(), theta) - tilts_.begin());
  double lo = r == 0 ? 0 : tilts_[r - 1];
  double u = (theta - lo) / (tilts_[r] - lo);
  if (r == 0) {
    out[0] = {0, 1 - u};
    ring(0, u, 1);
    return 3;
  }
  ring(r - 1, 1 - u, 0);
  ring(r, u, 2);
  return 4;
}

Frame tangent_frame(const Vec3& n, const Vec3& dpdu) {
  Vec3 t = dpdu - n * glm::dot(n, dpdu);
  double len = glm::length(t);
  if (!(len > 1e-12 * std::max(1.0, glm::length(dpdu)))) return frame_about(n);
  t /= len;
  return {t, glm::cross(n, t), n};
}

PerturbedMap::PerturbedMap(const Mesh& mesh, const std::vector<bool>& perturbed_objects,
                           const MapSettings& settings)
    : mesh_(mesh),
      directions_(settings),
      self_illumination_(settings.self_illumination),
      vertex_slot_(mesh.vertices.size(), -1),
      element_slot_(mesh.elements.size(), -1) {
  for (std::uint32_t e = 0; e < mesh.elements.size(); ++e) {
    const Element& el = mesh.elements[e];
    if (el.object >= perturbed_objects.size() || !perturbed_objects[el.object]) continue;
    element_slot_[e] = std::int32_t(slot_element_.size());
    slot_element_.push_back(e);
    Vec3 dpdu(0);
    for (int k = 0; k < el.vertex_count; ++k) {
      std::uint32_t v = el.v[k];
      dpdu += mesh.vertices[v].dpdu;
      if (vertex_slot_[v] >= 0) continue;
      vertex_slot_[v] = std::int32_t(slot_vertex_.size());
      slot_vertex_.push_back(v);
    }
    element_frames_.push_back(tangent_frame(el.normal, dpdu));
  }
  const std::size_t d = directions_.size();
  values_.assign(slot_vertex_.size() * d, Rgb(0));
  element_received_.assign(slot_element_.size() * d, Rgb(0));
  scratch_.assign(slot_element_.size() * (d + 1), 0.0);
}

std::span<const Rgb> PerturbedMap::samples(std::uint32_t slot) const {
  return {values_.data() + std::size_t(slot) * directions_.size(), directions_.size()};
}

std::span<Rgb> PerturbedMap::samples(std::uint32_t slot) {
  return {values_.data() + std::size_t(slot) * directions_.size(), directions_.size()};
}

Rgb PerturbedMap::lookup(std::uint32_t slot, const Vec3& local) const {
  std::array<DirectionSet::Weight, 4> w;
  int n = directions_.weights(local, w);
  auto s = samples(slot);
  Rgb b(0);
  for (int i = 0; i < n; ++i) b += w[i].weight * s[w[i].sample];
  return b;
}

void PerturbedMap::gather(const std::vector<Material>& materials, std::span<const Rgb> radiosity,
                          Hemicube& hemicube, std::stop_token stop) {
  const DeltaFormFactors& df = hemicube.deltas();
  const std::size_t nd = directions_.size();
  // Per sample direction, the pixels behind the perturbed tangent plane (the shadowed
  // sliver of Fig. 3), and the self-illumination form factor F'_ii = 1 - what stays in front.
  std::vector<std::vector<std::uint32_t>> sliver(nd);
  std::vector<double> self(nd, 1.0);
  for (std::size_t p = 0; p < df.size(); ++p) {
    Vec3 k = glm::dvec3(df.directional(p));
    for (std::size_t s = 0; s < nd; ++s) {
      double w = glm::dot(directions_.direction(s), k);
      if (w <= 0)
        sliver[s].push_back(std::uint32_t(p));
      else
        self[s] -= w;
    }
  }
  std::vector<Rgb> own;
  if (self_illumination_) own = vertex_radiosity(mesh_, radiosity);
  std::vector<int> material(slot_vertex_.size(), 0);
  for (std::uint32_t e : slot_element_)
    for (int k = 0; k < mesh_.elements[e].vertex_count; ++k)
      material[std::size_t(vertex_slot_[mesh_.elements[e].v[k]])] = mesh_.elements[e].material;

  const double lift = mesh_.diagonal() * 1e-6;
  for (std::uint32_t slot = 0; slot < slot_vertex_.size() && !stop.stop_requested(); ++slot) {
    const Vertex& v = mesh_.vertices[slot_vertex_[slot]];
    hemicube.render(v.position + v.normal * lift, tangent_frame(v.normal, v.dpdu), std::nullopt);
    auto ids = hemicube.item_buffer();
    // S: the radiosity-weighted directional sums of eq. 18-19, one 3-vector per channel.
    std::array<Vec3, 3> sum{Vec3(0), Vec3(0), Vec3(0)};
    for (std::size_t p = 0; p < ids.size(); ++p) {
      if (!ids[p]) continue;
      const Rgb& b = radiosity[ids[p] - 1];
      Vec3 k = glm::dvec3(df.directional(p));
      for (int c = 0; c < 3; ++c) sum[std::size_t(c)] += b[c] * k;
    }
    const Material& m = materials[std::size_t(material[slot])];
    auto out = samples(slot);
    for (std::size_t s = 0; s < nd; ++s) {
      const Vec3& n = directions_.direction(s);
      Rgb in(glm::dot(n, sum[0]), glm::dot(n, sum[1]), glm::dot(n, sum[2]));
      for (std::uint32_t p : sliver[s])
        if (ids[p]) in -= radiosity[ids[p] - 1] * glm::dot(n, glm::dvec3(df.directional(p)));
      out[s] = m.emission + m.reflectance * in;  // eq. 10
      if (self_illumination_) out[s] += m.reflectance * own[slot_vertex_[slot]] * self[s];
    }
  }
}

void PerturbedMap::shoot(const Hemicube& hemicube, const Frame& shooter, const Vec3& origin,
                         const Rgb& power, std::span<const VisibleElement> used) {
  if (slot_element_.empty()) return;
  const DeltaFormFactors& df = hemicube.deltas();
  const std::size_t nd = directions_.size();
  auto ids = hemicube.item_buffer();
  // F''_ji(N'_s) = sum over j's pixels q showing i of dF_q max(0, N'.(-d_q)) / (N_i.(-d_q))
  // (eq. 20), in the receiving element's own tangent frame; the last entry sums F_ji.
  // The hemi-cube lists the pixels of perturbed elements (Hemicube::watch).
  for (std::uint32_t p : hemicube.watched_pixels()) {
    std::int32_t es = element_slot_[ids[p] - 1];
    double* acc = &scratch_[std::size_t(es) * (nd + 1)];
    Vec3 to_shooter = -glm::normalize(shooter.to_world(glm::dvec3(df.direction(p))));
    Vec3 local = element_frames_[std::size_t(es)].to_local(to_shooter);
    double f = df.dF(p) / std::max(local.z, kMinCosine);
    for (std::size_t s = 0; s < nd; ++s)
      acc[s] += f * std::max(0.0, glm::dot(directions_.direction(s), local));
    acc[nd] += df.dF(p);
  }
  // dB'_i(N') = rho_i dB_j F''_ji(N') A_j / A_i (eq. 22), with F'' scaled like the solver's
  // own F_ji so that near-field corrections carry over; rho is applied in finish_shooting.
  for (const VisibleElement& v : used) {
    std::int32_t es = element_slot_[v.element];
    if (es < 0) continue;
    double* acc = &scratch_[std::size_t(es) * (nd + 1)];
    if (!(acc[nd] > 0)) {
      receive_ray(v.element, glm::normalize(origin - mesh_.elements[v.element].centroid),
                  power * v.form_factor);
      continue;
    }
    double scale = v.form_factor / acc[nd];
    Rgb h = power * (scale / mesh_.elements[v.element].area);
    for (std::size_t s = 0; s < nd; ++s) element_received_[std::size_t(es) * nd + s] += h * acc[s];
    std::fill(acc, acc + nd + 1, 0.0);
  }
}

void PerturbedMap::receive_ray(std::uint32_t element, const Vec3& to_source, const Rgb& power) {
  std::int32_t es = element_slot_[element];
  if (es < 0) return;
  const std::size_t nd = directions_.size();
  Vec3 local = element_frames_[std::size_t(es)].to_local(to_source);
  // As in eq. 20 for one pixel: the irradiance scales by cos' / cos, cos held as in shoot().
  Rgb h = power / (mesh_.elements[element].area * std::max(local.z, kMinCosine));
  for (std::size_t s = 0; s < nd; ++s)
    element_received_[std::size_t(es) * nd + s] +=
        h * std::max(0.0, glm::dot(directions_.direction(s), local));
}

std::vector<bool> PerturbedMap::perturbed_elements() const {
  std::vector<bool> out(element_slot_.size());
  for (std::size_t e = 0; e < out.size(); ++e) out[e] = element_slot_[e] >= 0;
  return out;
}

void PerturbedMap::finish_shooting(const std::vector<Material>& materials) {
  const std::size_t nd = directions_.size();
  std::fill(values_.begin(), values_.end(), Rgb(0));
  std::vector<double> area(slot_vertex_.size(), 0.0);
  for (std::size_t es = 0; es < slot_element_.size(); ++es) {
    const Element& e = mesh_.elements[slot_element_[es]];
    const Material& m = materials[std::size_t(e.material)];
    for (int k = 0; k < e.vertex_count; ++k) {
      std::size_t slot = std::size_t(vertex_slot_[e.v[k]]);
      area[slot] += e.area;
      for (std::size_t s = 0; s < nd; ++s)
        values_[slot * nd + s] +=
            e.area * (m.emission + m.reflectance * element_received_[es * nd + s]);
    }
  }
  for (std::size_t slot = 0; slot < area.size(); ++slot)
    for (std::size_t s = 0; s < nd; ++s) values_[slot * nd + s] /= area[slot];
}

}  // namespace bumprad
