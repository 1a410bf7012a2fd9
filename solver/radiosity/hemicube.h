// The hemi-cube (Cohen & Greenberg 1985): an item buffer of element ids rendered with OSMesa
// around a point, and the delta form-factor tables (paper eq. 12 and 17) that turn its
// pixels into point-to-element form factors.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "solver/radiosity/group_proxies.h"
#include "solver/radiosity/visible_element.h"
#include "solver/scene/mesh.h"
#include "solver/util/frame.h"
#include "solver/util/gl_context.h"

namespace bumprad {

// Item-buffer layout, R = resolution: the top face (R x R) in rows [0, R), then the upper
// halves of the +x, -x, +y and -y side faces (R x R/2 each). Row 0 is the bottom row.
class DeltaFormFactors {
 public:
  explicit DeltaFormFactors(int resolution);

  int resolution() const { return resolution_; }
  int width() const { return resolution_; }
  int height() const { return 3 * resolution_; }
  std::size_t size() const { return df_.size(); }

  // dF_p = (N . R_p) dA / (pi r^4), normalised so the whole hemi-cube sums to 1 (eq. 12).
  float dF(std::size_t p) const { return df_[p]; }
  // R_p: centre-to-pixel vector in the local frame, on the unit cube (not normalised).
  const glm::vec3& direction(std::size_t p) const { return direction_[p]; }
  // (dF_px, dF_py, dF_pz): eq. 17 with the same normalisation; dF_pz == dF_p.
  glm::vec3 directional(std::size_t p) const { return direction_[p] * weight_[p]; }

  // The pixel a local direction passes through, or size() for one below the tangent plane.
  std::size_t pixel_for(const Vec3& local) const;
  // The pixel of p's mirror direction (x, y, z) -> (-x, -y, z): a perfect mirror's lobe.
  std::size_t mirror(std::size_t p) const { return mirror_[p]; }

 private:
  int resolution_;
  std::vector<float> df_;
  std::vector<float> weight_;  // dA / (pi r^4), normalised
  std::vector<glm::vec3> direction_;
  std::vector<std::uint32_t> mirror_;
};

class Hemicube {
 public:
  // Uploads the elements once; `resolution` must be even.
  Hemicube(const Mesh& mesh, int resolution);

  // Renders the item buffer from `origin` (already lifted off its surface) looking along
  // frame.z. Elements of `skip_patch` (the shooter itself) are not drawn.
  void render(const Vec3& origin, const Frame& frame, std::optional<std::uint32_t> skip_patch);

  // Element id + 1 per pixel, 0 where nothing is seen; valid after render().
  std::span<const std::uint32_t> item_buffer() const;

  // F for every element seen in the last render: the sum of its pixels' dF (eq. 11-12).
  // The list is the caller's to adjust until the next call (e.g. near-field corrections).
  std::vector<VisibleElement>& form_factors();
  // The same for light leaving the origin in `lobes` (local frame; clusters.h's
  // member_lobes()): a pixel weighs sum max(0, lobe . R_p) dA / (pi r^4), the share a point
  // with that intensity sends through it. Lists no watched pixels.
  std::vector<VisibleElement>& form_factors(std::span<const Vec3> lobes);

  // From now on, draws a group far off by a proxy (group_proxies.h): the coarsest whose error
  // is under a quarter of a pixel as far off as the group lies. Its pixels then show ids of
  // its elements near the right ones, not the right ones: for callers that take a group's
  // light from its whole (shots), not from each pixel's element (a gather).
  void use_proxies(GroupProxies proxies);
  // Elements whose pixels form_factors() should also list (e.g. the bumpy ones the
  // perturbed map shoots to), so that nobody scans the item buffer a second time. Their
  // groups are drawn as they are.
  void watch(std::vector<bool> elements);
  // The pixels of watched elements seen in the last form_factors() call.
  const std::vector<std::uint32_t>& watched_pixels() const { return watched_pixels_; }

  const DeltaFormFactors& deltas() const { return deltas_; }
  // Time spent rendering and accumulating, in all since it was made.
  double render_seconds() const { return render_seconds_; }
  double accumulate_seconds() const { return accumulate_seconds_; }

 private:
  template <typename Weight>
  std::vector<VisibleElement>& accumulate(Weight weight, bool watching);
  // Each element's id + 1, for its four corners.
  std::vector<std::uint32_t> element_ids() const;
  // Hands corners_ and each corner's id + 1 to the GL buffers.
  void upload(std::span<const std::uint32_t> ids);

  const Mesh& mesh_;
  DeltaFormFactors deltas_;
  GlContext context_;
  unsigned vertex_buffer_ = 0, color_buffer_ = 0;
  // 4 per element (a triangle's last repeated), then 4 per proxy triangle; float.
  std::vector<glm::vec3> corners_;
  GroupProxies proxies_;
  std::vector<std::uint32_t> level_base_;  // per level, the first corner of its triangles,
                                           // then of its skirts
  std::vector<bool> whole_;                // per group: drawn as it is (a watched element in it)
  std::vector<std::int8_t> level_;         // per group: the proxy's level in the last render, or -1
  std::array<std::vector<std::uint32_t>, 5> face_indices_;  // per face, reused each render
  std::vector<double> sums_;
  std::vector<VisibleElement> visible_;
  std::vector<bool> watched_;
  std::vector<std::uint32_t> watched_pixels_;
  double render_seconds_ = 0, accumulate_seconds_ = 0;
};

}  // namespace bumprad
