#include "clients/progress_bar.h"

#include <algorithm>
#include <cstdio>

namespace bumprad {

std::string progress_line(int shots, int max_shots, double unshot_fraction, int step,
                          double seconds, int width) {
  const double done = max_shots > 0 ? std::clamp(double(shots) / max_shots, 0.0, 1.0) : 0.0;
  const std::size_t inside = std::size_t(std::max(0, width));
  const std::size_t filled = std::size_t(done * double(inside) + 1e-9);
  std::string line = "[";
  line.append(filled, '#');
  line.append(inside - filled, '-');
  line += ']';
  char text[128];
  std::snprintf(text, sizeof text, " %3d%%  %d/%d shots  unshot %.2f%%  step %d  %.1f s",
                int(100 * done), shots, max_shots, 100 * unshot_fraction, step, seconds);
  return line + text;
}

}  // namespace bumprad
