// Deadlines stop their stop sources, say so, and only while their guard lives; a stop for
// another reason is not a time-out. The deadlines are far shorter or far longer than any
// wait here, so the machine's speed does not decide the outcome.
#include "server/watchdog.h"

#include <thread>

#include <gtest/gtest.h>

namespace bumprad {
namespace {

bool stops_within(const std::stop_source& stop, std::chrono::seconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (!stop.stop_requested() && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return stop.stop_requested();
}

TEST(Watchdog, APassedDeadlineStopsTheSourceAndSaysSo) {
  Watchdog watchdog;
  std::stop_source stop;
  Watchdog::Guard guard(watchdog, stop, std::chrono::milliseconds(20));
  EXPECT_TRUE(stops_within(stop, std::chrono::seconds(30)));
  EXPECT_TRUE(guard.timed_out());
}

TEST(Watchdog, TheEarliestDeadlineFiresFirstAndOthersWait) {
  Watchdog watchdog;
  std::stop_source late, soon;
  Watchdog::Guard late_guard(watchdog, late, std::chrono::hours(1));
  Watchdog::Guard soon_guard(watchdog, soon, std::chrono::milliseconds(10));
  EXPECT_TRUE(stops_within(soon, std::chrono::seconds(30)));
  EXPECT_FALSE(late.stop_requested());
  EXPECT_FALSE(late_guard.timed_out());
}

TEST(Watchdog, AGuardGoneOrAStopForAnotherReasonIsNoTimeout) {
  Watchdog watchdog;
  std::stop_source cancelled;
  {
    Watchdog::Guard guard(watchdog, cancelled, std::chrono::hours(1));
    cancelled.request_stop();  // a DELETE, say
    EXPECT_FALSE(guard.timed_out());
  }
  std::stop_source finished;
  { Watchdog::Guard guard(watchdog, finished, std::chrono::milliseconds(500)); }
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  EXPECT_FALSE(finished.stop_requested());  // the job ended in time: its guard went with it
}

}  // namespace
}  // namespace bumprad
