#include "server/watchdog.h"

#include <algorithm>

namespace bumprad {

Watchdog::Watchdog() : thread_([this] { run(); }) {}

Watchdog::~Watchdog() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

Watchdog::Guard::Guard(Watchdog& watchdog, std::stop_source stop,
                       std::chrono::duration<double> limit)
    : watchdog_(watchdog) {
  {
    std::lock_guard lock(watchdog_.mutex_);
    id_ = watchdog_.next_id_++;
    auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(limit);
    watchdog_.entries_.emplace(id_, Entry{std::move(stop), deadline});
  }
  watchdog_.wake_.notify_all();
}

Watchdog::Guard::~Guard() {
  std::lock_guard lock(watchdog_.mutex_);
  watchdog_.entries_.erase(id_);
}

bool Watchdog::Guard::timed_out() const {
  std::lock_guard lock(watchdog_.mutex_);
  return watchdog_.entries_.at(id_).fired;
}

void Watchdog::run() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    auto next = Clock::time_point::max();
    const auto now = Clock::now();
    for (auto& [id, e] : entries_) {
      if (e.fired) continue;
      if (e.deadline <= now) {
        e.fired = true;
        e.stop.request_stop();  // only sets a flag: cheap under the lock
      } else {
        next = std::min(next, e.deadline);
      }
    }
    if (next == Clock::time_point::max())
      wake_.wait(lock);
    else
      wake_.wait_until(lock, next);
  }
}

}  // namespace bumprad
