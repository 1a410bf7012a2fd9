#include "solver/radiosity/perturbed_map.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "solver/radiosity/vertex_radiosity.h"
#include "solver/scene/geometry.h"

namespace bumprad {
namespace {

// Shooting divides by the receiver's cosine toward the shooter (eq. 20). A grazing pixel
// would make that ratio blow up on aliasing noise; below this cosine (about 3 degrees
// above the surface) the divisor is held, which bounds the ratio by 1 / kMinCosine.
constexpr double kMinCosine = 0.05;

}  // namespace

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
      basis_(settings),
      unperturbed_(basis_.evaluate(Vec3(0, 0, 1))),
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
  const std::size_t n = basis_.size();
  values_.assign(slot_vertex_.size() * n, Rgb(0));
  element_received_.assign(slot_element_.size() * n, Rgb(0));
  scratch_.assign(slot_element_.size() * (n + 1), 0.0);
  projected_.assign(n, 0.0);
}

std::span<const Rgb> PerturbedMap::values(std::uint32_t slot) const {
  return {values_.data() + std::size_t(slot) * basis_.size(), basis_.size()};
}

std::span<Rgb> PerturbedMap::values(std::uint32_t slot) {
  return {values_.data() + std::size_t(slot) * basis_.size(), basis_.size()};
}

Rgb PerturbedMap::value(std::uint32_t slot, const MapTerms& terms) const {
  const Rgb* v = values_.data() + std::size_t(slot) * basis_.size();
  Rgb b(0);
  for (std::size_t i = 0; i < std::size_t(terms.count); ++i)
    b += terms.weight[i] * v[terms.index[i]];
  return b;
}

Rgb PerturbedMap::lookup(std::uint32_t slot, const Vec3& local) const {
  return value(slot, basis_.evaluate(local));
}

void PerturbedMap::gather(const std::vector<Material>& materials, std::span<const Rgb> radiosity,
                          Hemicube& hemicube, std::stop_token stop) {
  const DeltaFormFactors& df = hemicube.deltas();
  const std::size_t n = basis_.size();
  // The surface around the vertex as seen from a tilted normal, below the tangent plane
  // (F'_ii of paper section 3): the hemi-cube's pixels mirrored to the lower hemisphere
  // give its solid angles.
  std::vector<double> self(n, 0.0);
  for (std::size_t p = 0; p < df.size(); ++p) {
    const Vec3 k = glm::dvec3(df.directional(p));
    const double dw = glm::length(k);  // solid angle / pi
    basis_.project(Vec3(k.x, k.y, -k.z) / dw, projected_);
    for (std::size_t i = 0; i < n; ++i) self[i] += dw * projected_[i];
  }
  std::vector<Rgb> own;
  if (self_illumination_) own = vertex_radiosity(mesh_, radiosity);
  std::vector<int> material(slot_vertex_.size(), 0);
  for (std::uint32_t e : slot_element_)
    for (int k = 0; k < mesh_.elements[e].vertex_count; ++k)
      material[std::size_t(vertex_slot_[mesh_.elements[e].v[k]])] = mesh_.elements[e].material;

  const double lift = hemicube_lift(mesh_);
  std::vector<Rgb> in(n);
  for (std::uint32_t slot = 0; slot < slot_vertex_.size() && !stop.stop_requested(); ++slot) {
    const Vertex& v = mesh_.vertices[slot_vertex_[slot]];
    hemicube.render(v.position + v.normal * lift, tangent_frame(v.normal, v.dpdu), std::nullopt);
    auto ids = hemicube.item_buffer();
    // Each pixel's radiosity times its solid angle / pi, projected (eq. 17-19).
    std::fill(in.begin(), in.end(), Rgb(0));
    for (std::size_t p = 0; p < ids.size(); ++p) {
      if (!ids[p]) continue;
      const Vec3 k = glm::dvec3(df.directional(p));
      const double dw = glm::length(k);
      basis_.project(k / dw, projected_);
      const Rgb b = radiosity[ids[p] - 1] * dw;
      for (std::size_t i = 0; i < n; ++i) in[i] += b * projected_[i];
    }
    const Material& m = materials[std::size_t(material[slot])];
    const Rgb around = self_illumination_ ? own[slot_vertex_[slot]] : Rgb(0);
    auto out = values(slot);
    for (std::size_t i = 0; i < n; ++i)  // eq. 10
      out[i] = m.emission * basis_.constant()[i] + m.reflectance * (in[i] + around * self[i]);
  }
}

void PerturbedMap::shoot(const Hemicube& hemicube, const Frame& shooter, const Vec3& origin,
                         const Rgb& power, std::span<const VisibleElement> used,
                         std::stop_token stop) {
  if (slot_element_.empty()) return;
  const DeltaFormFactors& df = hemicube.deltas();
  const std::size_t n = basis_.size();
  auto ids = hemicube.item_buffer();
  // F''_ji(N') = sum over j's pixels q showing i of dF_q max(0, N'.(-d_q)) / (N_i.(-d_q))
  // (eq. 20), in the receiving element's own tangent frame and projected into the basis
  // (the clamped cosine is MapBasis::project); the last entry sums F_ji. The hemi-cube
  // lists the pixels of perturbed elements (Hemicube::watch).
  for (std::uint32_t p : hemicube.watched_pixels()) {
    if (stop.stop_requested()) {
      std::fill(scratch_.begin(), scratch_.end(), 0.0);
      return;
    }
    std::int32_t es = element_slot_[ids[p] - 1];
    double* acc = &scratch_[std::size_t(es) * (n + 1)];
    Vec3 to_shooter = -glm::normalize(shooter.to_world(glm::dvec3(df.direction(p))));
    Vec3 local = element_frames_[std::size_t(es)].to_local(to_shooter);
    double f = df.dF(p) / std::max(local.z, kMinCosine);
    basis_.project(local, projected_);
    for (std::size_t i = 0; i < n; ++i) acc[i] += f * projected_[i];
    acc[n] += df.dF(p);
  }
  // dB'_i(N') = rho_i dB_j F''_ji(N') A_j / A_i (eq. 22), with F'' scaled like the solver's
  // own F_ji so that near-field corrections carry over; rho is applied in finish_shooting.
  for (const VisibleElement& v : used) {
    std::int32_t es = element_slot_[v.element];
    if (es < 0) continue;
    double* acc = &scratch_[std::size_t(es) * (n + 1)];
    if (!(acc[n] > 0)) {
      receive_ray(v.element, glm::normalize(origin - mesh_.elements[v.element].centroid),
                  power * v.form_factor);
      continue;
    }
    double scale = v.form_factor / acc[n];
    Rgb h = power * (scale / mesh_.elements[v.element].area);
    for (std::size_t i = 0; i < n; ++i) element_received_[std::size_t(es) * n + i] += h * acc[i];
    std::fill(acc, acc + n + 1, 0.0);
  }
}

void PerturbedMap::receive_ray(std::uint32_t element, const Vec3& to_source, const Rgb& power) {
  std::int32_t es = element_slot_[element];
  if (es < 0) return;
  const std::size_t n = basis_.size();
  Vec3 local = element_frames_[std::size_t(es)].to_local(to_source);
  // As in eq. 20 for one pixel: the irradiance scales by cos' / cos, cos held as in shoot().
  Rgb h = power / (mesh_.elements[element].area * std::max(local.z, kMinCosine));
  basis_.project(local, projected_);
  for (std::size_t i = 0; i < n; ++i)
    element_received_[std::size_t(es) * n + i] += h * projected_[i];
}

std::vector<bool> PerturbedMap::perturbed_elements() const {
  std::vector<bool> out(element_slot_.size());
  for (std::size_t e = 0; e < out.size(); ++e) out[e] = element_slot_[e] >= 0;
  return out;
}

void PerturbedMap::finish_shooting(const std::vector<Material>& materials) {
  const std::size_t n = basis_.size();
  std::fill(values_.begin(), values_.end(), Rgb(0));
  std::vector<double> area(slot_vertex_.size(), 0.0);
  for (std::size_t es = 0; es < slot_element_.size(); ++es) {
    const Element& e = mesh_.elements[slot_element_[es]];
    const Material& m = materials[std::size_t(e.material)];
    for (int k = 0; k < e.vertex_count; ++k) {
      std::size_t slot = std::size_t(vertex_slot_[e.v[k]]);
      area[slot] += e.area;
      for (std::size_t i = 0; i < n; ++i)
        values_[slot * n + i] += e.area * (m.emission * basis_.constant()[i] +
                                           m.reflectance * element_received_[es * n + i]);
    }
  }
  for (std::size_t slot = 0; slot < area.size(); ++slot)
    for (std::size_t i = 0; i < n; ++i) values_[slot * n + i] /= area[slot];
}

}  // namespace bumprad
