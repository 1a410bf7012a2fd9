#include "solver/util/frame.h"

#include <cmath>

namespace bumprad {

Frame frame_about(const Vec3& n, double angle) {
  Vec3 helper = std::abs(n.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  Vec3 x = glm::normalize(glm::cross(helper, n));
  Vec3 y = glm::cross(n, x);
  double c = std::cos(angle), s = std::sin(angle);
  return {c * x + s * y, -s * x + c * y, n};
}

}  // namespace bumprad
