// Wall-clock timing for solve statistics and benchmarks.
#pragma once

#include <chrono>

namespace bumprad {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace bumprad
