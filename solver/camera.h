// A pinhole camera: image-plane positions to world-space rays.
#pragma once

#include "solver/scene.h"

namespace bumprad {

struct Ray {
  Vec3 origin, direction;  // direction is unit length
};

class PinholeCamera {
 public:
  explicit PinholeCamera(const Camera& camera);
  // (x, y) in pixels from the top-left corner of the image; (0.5, 0.5) is the first centre.
  Ray ray(double x, double y) const;

 private:
  Vec3 position_, forward_, right_, up_;
  double half_height_, half_width_;
  int width_, height_;
};

}  // namespace bumprad
