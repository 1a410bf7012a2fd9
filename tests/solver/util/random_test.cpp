// The solver's random numbers are the same on every standard library: the Mersenne Twister
// stream reproduces generate_canonical as libstdc++ computes it (the solves' hemi-cube turns
// were drawn that way before random.h owned them), and shuffles are permutations that depend
// only on the seed.
#include "solver/util/random.h"

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace bumprad {
namespace {

#ifdef __GLIBCXX__
TEST(Random, MersenneTwisterDrawsAsLibstdcxxGenerateCanonical) {
  for (std::uint32_t seed : {1u, 7u, 123456789u}) {
    MersenneTwister ours(seed);
    std::mt19937 theirs(seed);
    for (int i = 0; i < 10000; ++i)
      ASSERT_EQ(ours.next(), (std::generate_canonical<double, 53>(theirs))) << seed << " " << i;
  }
}
#endif

// The standard fixes mt19937's 10,000th output for the default seed (5489): 4123659995.
TEST(Random, MersenneTwisterIsTheStandardEngine) {
  std::mt19937 engine;
  engine.discard(9999);
  EXPECT_EQ(engine(), 4123659995u);
  MersenneTwister first(5489);
  EXPECT_EQ(first.next(), (3499211612.0 + 581869302.0 * 0x1.0p32) / 0x1.0p64);
}

TEST(Random, DrawsAreUniformInTheUnitInterval) {
  for (auto draw : {+[](std::uint64_t s) {
                      Random r(s);
                      std::vector<double> v(100000);
                      for (double& x : v) x = r.next();
                      return v;
                    },
                    +[](std::uint64_t s) {
                      MersenneTwister r{std::uint32_t(s)};
                      std::vector<double> v(100000);
                      for (double& x : v) x = r.next();
                      return v;
                    }}) {
    const std::vector<double> v = draw(3);
    int bins[10] = {};
    for (double x : v) {
      ASSERT_GE(x, 0.0);
      ASSERT_LT(x, 1.0);
      ++bins[int(x * 10)];
    }
    // 10,000 expected a bin, standard deviation 95: 5 sigma.
    for (int b : bins) EXPECT_NEAR(b, 10000, 475);
  }
}

TEST(Random, ShuffleIsAPermutationThatDependsOnlyOnTheSeed) {
  std::vector<int> a(1000), b(1000);
  std::iota(a.begin(), a.end(), 0);
  b = a;
  Random ra(hash64(5)), rb(hash64(5));
  shuffle(std::span(a), ra);
  shuffle(std::span(b), rb);
  EXPECT_EQ(a, b);
  int moved = 0;
  for (int i = 0; i < 1000; ++i) moved += a[std::size_t(i)] != i;
  EXPECT_GT(moved, 900);  // about 999 expected
  std::sort(a.begin(), a.end());
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(a[std::size_t(i)], i);
}

// The first 2^m points of a scrambled (0,2)-sequence are a (0,m,2)-net: one point in each
// box of every dyadic shape of area 2^-m (here m = 2 and m = 6, for several scrambles), and
// the first 4 of the first 64 are the first net again.
TEST(Random, Sobol02PointsStratifyEveryDyadicShape) {
  for (std::uint64_t seed : {1, 2, 3}) {
    Random random(seed);
    const Sobol02 points(random);
    for (int m : {2, 6}) {
      const int count = 1 << m;
      for (int k = 0; k <= m; ++k) {  // boxes of 2^-k by 2^-(m-k)
        std::vector<int> in(std::size_t(count), 0);
        for (int i = 0; i < count; ++i) {
          const auto [u, v] = points[std::uint32_t(i)];
          ASSERT_GE(u, 0);
          ASSERT_LT(u, 1);
          ASSERT_GE(v, 0);
          ASSERT_LT(v, 1);
          const int bx = int(u * (1 << k)), by = int(v * (1 << (m - k)));
          ++in[std::size_t(bx * (1 << (m - k)) + by)];
        }
        for (int n : in) EXPECT_EQ(n, 1) << "seed " << seed << " m " << m << " k " << k;
      }
    }
  }
}

}  // namespace
}  // namespace bumprad
