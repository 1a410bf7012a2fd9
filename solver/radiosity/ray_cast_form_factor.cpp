#include "solver/radiosity/ray_cast_form_factor.h"

#include <glm/geometric.hpp>

namespace bumprad {

double ray_cast_form_factor(const Vec3& receiver, const Vec3& receiver_normal,
                            std::span<const AreaSample> source, const RayScene* rays,
                            double offset) {
  const Vec3 from = receiver + receiver_normal * offset;
  double f = 0;
  for (const AreaSample& s : source) {
    Vec3 d = s.point - receiver;
    double r2 = glm::dot(d, d);
    if (!(r2 > 0)) continue;
    Vec3 w = d / std::sqrt(r2);
    double cos_r = glm::dot(receiver_normal, w);
    double cos_s = -glm::dot(s.normal, w);
    if (cos_r <= 0 || cos_s <= 0) continue;
    if (rays) {
      Vec3 to = s.point + s.normal * offset;
      Vec3 path = to - from;
      double length = glm::length(path);
      if (length > 0 && rays->occluded({from, path / length}, length)) continue;
    }
    f += wallace_term(cos_r, cos_s, s.area, r2);
  }
  return f;
}

}  // namespace bumprad
