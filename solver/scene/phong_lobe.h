// The glossy lobe of a non-diffuse material: Phong's cos^n about the mirror direction,
// renormalised over the directions above the surface (what falls below is drawn again), so
// a glossy surface reflects exactly k_s of what it receives. One definition for the solver's
// second pass, the view pass and the path tracer, which must all mean the same material.
#pragma once

#include "solver/util/frame.h"
#include "solver/util/math.h"
#include "solver/util/random.h"

namespace bumprad {

class PhongLobe {
 public:
  // `mirror`: the mirror direction; `normal`: the (shading) normal that bounds the lobe.
  PhongLobe(const Vec3& mirror, const Vec3& normal, double exponent);

  // The direction for u1 in [0,1) and u2 in turns on the whole lobe (cos a = u1^(1/(n+1)),
  // azimuth 2 pi u2); it may point below the surface (the caller then draws again).
  Vec3 direction(double u1, double u2) const;
  // A direction drawn from the renormalised lobe; false if 64 draws all fell below.
  bool sample(Random& random, Vec3& out) const;
  // Density per solid angle of sample()'s directions: (n+1)/(2 pi) cos^n a / above().
  double pdf(const Vec3& d) const;
  // The share of the unbounded lobe above the surface (computed on first use: sampling alone
  // does not need it).
  double above() const;

 private:
  Frame frame_;
  Vec3 normal_;
  double exponent_;
  mutable double above_ = -1;
};

}  // namespace bumprad
