// Every random number of the solver comes from here, the same on every compiler and standard
// library. Random: a small counter-based generator (splitmix64, Steele et al. 2014);
// renderers seed one per pixel and sample, so images do not depend on threads or the order
// of rows. MersenneTwister: the solve's stream of hemi-cube turns.
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <utility>

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

// Shuffles `items` (Fisher-Yates, one Random draw an item).
template <typename T>
void shuffle(std::span<T> items, Random& random) {
  for (std::size_t i = items.size(); i > 1; --i)
    std::swap(items[i - 1], items[std::size_t(random.next() * double(i))]);
}

// std::mt19937, whose sequence the C++ standard fixes, drawn as uniform doubles the way
// generate_canonical<double, 53> is specified and libstdc++ computes it (two draws, the
// first the low word). std::uniform_real_distribution is not specified to the bit, so its
// numbers differ between standard libraries; these do not.
class MersenneTwister {
 public:
  explicit MersenneTwister(std::uint32_t seed) : engine_(seed) {}
  // Uniform in [0, 1).
  double next() {
    const double low = double(engine_());
    const double sum = low + double(engine_()) * 0x1.0p32;
    const double u = sum / 0x1.0p64;
    return u < 1 ? u : 0x1.fffffffffffffp-1;
  }

 private:
  std::mt19937 engine_;
};

}  // namespace bumprad
