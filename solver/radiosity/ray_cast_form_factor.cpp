#include "solver/radiosity/ray_cast_form_factor.h"

#include <glm/geometric.hpp>

namespace bumprad {

double ray_cast_form_factor(const Vec3& receiver, const Vec3& receiver_normal,
                            std::span<const AreaSample> source, const RayScene* rays,
                            double offset) {
  const Vec3 from = receiver + receiver_normal * offset;
  double f = 0;
  for (const AreaSample& s : source) {
    // The cosines times r (no square root: this loop is much of a shot's groups' pass).
    const Vec3 d = s.point - receiver;
    const double r2 = glm::dot(d, d);
    const double cos_r = glm::dot(receiver_normal, d), cos_s = -glm::dot(s.normal, d);
    if (!(r2 > 0) || cos_r <= 0 || cos_s <= 0) continue;
    if (rays) {
      Vec3 to = s.point + s.normal * offset;
      Vec3 path = to - from;
      double length = glm::length(path);
      if (length > 0 && rays->occluded({from, path / length}, length)) continue;
    }
    f += wallace_term(cos_r, cos_s, s.area, r2) / r2;
  }
  return f;
}

}  // namespace bumprad
