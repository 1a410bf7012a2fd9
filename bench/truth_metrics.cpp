#include "bench/truth_metrics.h"

#include <algorithm>
#include <cmath>

namespace bumprad {

Comparison compare(const Image& a, const Image& r, const std::vector<bool>& emitter) {
  double diff[2] = {0, 0}, norm[2] = {0, 0}, sa = 0, sr = 0;
  for (std::size_t i = 0; i < r.rgb.size(); ++i) {
    const double d = double(a.rgb[i]) - double(r.rgb[i]);
    const bool surface = !emitter[i / 3];
    for (int k = 0; k < 2; ++k)
      if (k == 0 || surface) {
        diff[k] += d * d;
        norm[k] += double(r.rgb[i]) * double(r.rgb[i]);
      }
    if (surface) sa += a.rgb[i], sr += r.rgb[i];
  }
  return {std::sqrt(diff[1] / norm[1]), std::sqrt(diff[0] / norm[0]), sa / sr};
}

double without_noise(double measured, double noise) {
  return std::sqrt(std::max(0.0, measured * measured - noise * noise));
}

}  // namespace bumprad
