// parallel_for runs every index exactly once, whatever the count, and a stop ends it early.
#include "solver/util/parallel.h"

#include <atomic>
#include <vector>

#include <gtest/gtest.h>

namespace bumprad {
namespace {

TEST(Parallel, EveryIndexRunsExactlyOnce) {
  for (int count : {0, 1, 2, 7, 1000, 100000}) {
    std::vector<std::atomic<int>> runs(static_cast<std::size_t>(count));
    parallel_for(count, [&](int i) { runs[std::size_t(i)].fetch_add(1); });
    for (int i = 0; i < count; ++i) ASSERT_EQ(runs[std::size_t(i)].load(), 1) << count << " " << i;
  }
}

TEST(Parallel, AStopEndsItBeforeTheNextIndex) {
  std::stop_source stop;
  std::atomic<int> ran{0};
  parallel_for(
      1000000,
      [&](int) {
        if (ran.fetch_add(1) == 10) stop.request_stop();
      },
      stop.get_token());
  // Each thread may finish the index it holds: at most one more per thread after the stop.
  EXPECT_LT(ran.load(), 1000);
  std::atomic<int> none{0};
  parallel_for(
      100, [&](int) { none.fetch_add(1); }, stop.get_token());
  EXPECT_EQ(none.load(), 0);
}

}  // namespace
}  // namespace bumprad
