// Wall-clock timing for solve statistics and benchmarks, and the Unix time job records keep.
#pragma once

#include <chrono>

namespace bumprad {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline double unix_now() {
  using namespace std::chrono;
  return duration<double>(system_clock::now().time_since_epoch()).count();
}

}  // namespace bumprad
