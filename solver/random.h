// A small counter-based random generator (splitmix64, Steele et al. 2014). Renderers seed
// one per pixel and sample, so images do not depend on threads or the order of rows.
#pragma once

#include <cstdint>

namespace bumprad {

// A well-mixed 64-bit function of x (splitmix64's finaliser), for seeding many independent
// streams: seeds k apart by the increment below would give the same sequence shifted by k.
inline std::uint64_t hash64(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  // Uniform in [0, 1).
  double next() { return double(hash64(state_ += 0x9e3779b97f4a7c15ull) >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

}  // namespace bumprad
