#include "solver/radiosity/specular_transfer.h"

#include <algorithm>
#include <array>
#include <numbers>

#include <glm/geometric.hpp>

#include "solver/radiosity/hemicube.h"
#include "solver/radiosity/perturbed_map.h"
#include "solver/scene/phong_lobe.h"

namespace bumprad {

SpecularTransfer::SpecularTransfer(const Mesh& mesh, const std::vector<Material>& materials)
    : mesh_(mesh),
      shininess_(mesh.elements.size()),
      source_slot_(mesh.patches.size(), -1),
      incident_(mesh.elements.size(), Rgb(0)),
      incident_emission_(mesh.elements.size(), Rgb(0)) {
  for (std::size_t i = 0; i < mesh.elements.size(); ++i)
    shininess_[i] = materials[std::size_t(mesh.elements[i].material)].shininess;
}

// One transfer as it goes: the hemi-cube it reads, and where the light went.
struct SpecularTransfer::Pass {
  const DeltaFormFactors& d;
  std::span<const std::uint32_t> ids;
  const Frame& frame;
  PerturbedMap* map;
  bool exact;
  double shininess;
  // A curved glossy patch (a sphere's) reflects about its elements' normals in turn, not
  // about its centre's alone: the light it throws spreads as the surface turns.
  std::vector<Vec3> normals;  // local
  Result result;
  std::vector<std::uint32_t> touched;
};

// Each source's pixels on this hemi-cube: where its light came in from (P in eq. 5).
std::vector<std::vector<std::uint32_t>> SpecularTransfer::source_pixels(
    std::span<const std::uint32_t> ids, std::span<const Queued> sources) {
  std::vector<std::vector<std::uint32_t>> pixels(sources.size());
  for (std::size_t k = 0; k < sources.size(); ++k)
    source_slot_[sources[k].source] = std::int32_t(k);
  for (std::size_t p = 0; p < ids.size(); ++p)
    if (ids[p])
      if (std::int32_t k = source_slot_[mesh_.elements[ids[p] - 1].patch]; k >= 0)
        pixels[std::size_t(k)].push_back(std::uint32_t(p));
  for (const Queued& s : sources) source_slot_[s.source] = -1;
  return pixels;
}

// Power leaving through pixel q. With exact direct light (`exact`) the map gets no part of
// an emitter's image: the view pass computes that light itself.
void SpecularTransfer::deposit(Pass& pass, std::size_t q, const Rgb& power, const Rgb& emission) {
  if (q >= pass.ids.size() || !pass.ids[q]) {
    pass.result.escaped += power;
    return;
  }
  std::uint32_t i = pass.ids[q] - 1;
  if (incident_[i] == Rgb(0)) pass.touched.push_back(i);
  incident_[i] += power;
  incident_emission_[i] += emission;
  if (pass.map)
    pass.map->receive_ray(i, -glm::normalize(pass.frame.to_world(Vec3(pass.d.direction(q)))),
                          pass.exact ? power - emission : power);
}

// The Phong lobe about the mirror direction, importance-sampled (pdf ~ cos^n) on 32 strata
// (8 rings of 4) turned per pixel; samples below the surface are dropped and the rest
// renormalised, so exactly the queued power leaves (the lobe conserves energy). A source
// seen in many pixels gives each pixel only its share of the 32 strata (`count` of them from
// `first`), the neighbours taking the others: a large source costs one sample a pixel, not
// 32 (with 32, paper-room's sphere spent longer on this than on its hemi-cube).
void SpecularTransfer::reflect(Pass& pass, std::uint32_t p, const Rgb& power, const Rgb& emission,
                               int count, int first) {
  const DeltaFormFactors& d = pass.d;
  if (pass.shininess <= 0) return deposit(pass, d.mirror(p), power, emission);
  const Vec3 in(d.direction(p));
  std::array<std::size_t, kLobe> out;
  int valid = 0;
  for (int j = 0; j < count; ++j) {
    const int k = ((first + j) * 13) % kLobe;  // 13 is prime to 32: each stratum once
    const PhongLobe lobe(
        glm::reflect(-in, pass.normals[std::size_t(first + j) % pass.normals.size()]),
        Vec3(0, 0, 1), pass.shininess);
    // Each ring turned, the whole pattern turned per pixel (golden angle).
    const double turn = ((k / 4) * 0.7 + 2.399963 * p) / (2 * std::numbers::pi);
    std::size_t q =
        d.pixel_for(lobe.direction((k / 4 + 0.5) / (kLobe / 4), (k % 4 + 0.5) / 4 + turn));
    if (q < d.size()) out[std::size_t(valid++)] = q;
  }
  if (valid == 0) return deposit(pass, d.mirror(p), power, emission);
  for (int k = 0; k < valid; ++k)
    deposit(pass, out[std::size_t(k)], power / double(valid), emission / double(valid));
}

SpecularTransfer::Result SpecularTransfer::transfer(std::uint32_t pi, const Vec3& origin,
                                                    const Frame& frame, const Hemicube& hemicube,
                                                    std::span<const Queued> sources,
                                                    PerturbedMap* map, bool exact,
                                                    std::stop_token stop) {
  const DeltaFormFactors& d = hemicube.deltas();
  const Patch& shooter = mesh_.patches[pi];
  Pass pass{d, hemicube.item_buffer(), frame, map, exact, shininess_[shooter.first], {}, {}, {}};
  for (std::uint32_t e = shooter.first; e < shooter.first + shooter.count; ++e)
    pass.normals.push_back(frame.to_local(mesh_.elements[e].normal));
  const auto pixels = source_pixels(pass.ids, sources);
  for (std::size_t k = 0; k < sources.size() && !stop.stop_requested(); ++k) {
    const Queued& s = sources[k];
    double f = 0;
    for (std::uint32_t p : pixels[k]) f += d.dF(p);
    if (f > 0) {
      const int count = std::max(1, kLobe / int(std::min<std::size_t>(pixels[k].size(), kLobe)));
      for (std::size_t j = 0; j < pixels[k].size(); ++j) {  // H_p of eq. 5
        if (stop.stop_requested()) break;
        const std::uint32_t p = pixels[k][j];
        reflect(pass, p, s.power * (d.dF(p) / f), s.emission * (d.dF(p) / f), count,
                int(j % kLobe) * count);
      }
      continue;
    }
    // The source is hidden from the patch centre (it lit only part of the patch): its light
    // still arrived along the direction of its centre.
    Vec3 to_source = mesh_.patches[s.source].centroid - origin;
    std::size_t p = d.pixel_for(frame.to_local(glm::normalize(to_source)));
    if (p < d.size())
      reflect(pass, std::uint32_t(p), s.power, s.emission, kLobe, 0);
    else
      pass.result.escaped += s.power;
  }
  for (std::uint32_t i : pass.touched) {
    pass.result.arrivals.push_back({i, incident_[i], incident_emission_[i]});
    incident_[i] = incident_emission_[i] = Rgb(0);
  }
  return pass.result;
}

}  // namespace bumprad
