// Every random number of the solver comes from here, the same on every compiler and standard
// library. Random: a small counter-based generator (splitmix64, Steele et al. 2014);
// renderers seed one per pixel and sample, so images do not depend on threads or the order
// of rows. MersenneTwister: the solve's stream of hemi-cube turns. Sobol02: stratified
// points in the square, for integrands with edges (a shadow's penumbra).
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
  std::uint32_t bits() { return std::uint32_t(hash64(state_ += 0x9e3779b97f4a7c15ull) >> 32); }
  std::uint64_t bits64() { return hash64(state_ += 0x9e3779b97f4a7c15ull); }

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

// The (0,2)-sequence in base 2 (van der Corput's and Sobol's second dimension), each
// coordinate scrambled by a random digital shift (XOR), which keeps its strata: any first
// 2^m points form a (0,m,2)-net, one point in every one of the 2^m boxes of area 2^-m of
// each dyadic shape (2^m x 1, ..., 1 x 2^m). So its first 4 points stratify the square 2 x 2,
// and 32 points, the first 4 among them, stratify it again 32-fold: a count can grow where
// the first samples disagree without throwing them away.
class Sobol02 {
 public:
  explicit Sobol02(Random& random) : shift_x_(random.bits()), shift_y_(random.bits()) {}
  // Shifted by the first draws of a Random seeded with `seed`.
  explicit Sobol02(std::uint64_t seed) {
    Random random(seed);
    *this = Sobol02(random);
  }
  std::pair<double, double> operator[](std::uint32_t i) const {
    std::uint32_t x = i, y = 0;
    x = (x << 16) | (x >> 16);  // bit reversal: the radical inverse of i in base 2
    x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
    for (std::uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1)
      if (i & 1) y ^= v;
    return {double(x ^ shift_x_) * 0x1.0p-32, double(y ^ shift_y_) * 0x1.0p-32};
  }

 private:
  std::uint32_t shift_x_ = 0, shift_y_ = 0;
};

}  // namespace bumprad
