// Wall-time limits: stop sources that a deadline stops. One thread sleeps until the earliest
// deadline; a solve or render checks its stop token inside every long loop, so work past its
// time limit ends mid-shot or within one image row.
#pragma once

#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <stop_token>
#include <thread>

namespace bumprad {

class Watchdog {
 public:
  using Clock = std::chrono::steady_clock;
  Watchdog();
  ~Watchdog();
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

  // While a Guard lives, `stop` is stopped once `limit` has passed; timed_out() then says so
  // (a stop for any other reason, a cancel, leaves it false).
  class Guard {
   public:
    Guard(Watchdog& watchdog, std::stop_source stop, std::chrono::duration<double> limit);
    ~Guard();
    Guard(const Guard&) = delete;
    Guard& operator=(const Guard&) = delete;
    bool timed_out() const;

   private:
    Watchdog& watchdog_;
    int id_;
  };

 private:
  struct Entry {
    std::stop_source stop;
    Clock::time_point deadline;
    bool fired = false;
  };
  void run();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::map<int, Entry> entries_;
  int next_id_ = 0;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace bumprad
