#include "server/job.h"

#include <vector>

namespace bumprad {

Job::View Job::view() const {
  std::lock_guard lock(mutex_);
  return {record_, preview_};
}

void Job::update(const std::function<void(JobRecord&)>& change) {
  {
    std::lock_guard lock(mutex_);
    change(record_);
  }
  wake();
}

void Job::publish_step(std::shared_ptr<const std::string> png,
                       const std::function<void(JobRecord&)>& change) {
  {
    std::lock_guard lock(mutex_);
    change(record_);
    preview_ = std::move(png);
  }
  wake();
}

int Job::watch(Watcher watcher) {
  std::lock_guard lock(mutex_);
  watchers_.emplace(next_watcher_, std::move(watcher));
  return next_watcher_++;
}

void Job::unwatch(int id) {
  std::lock_guard lock(mutex_);
  watchers_.erase(id);
}

void Job::wake() {
  std::vector<Watcher> to_call;
  {
    std::lock_guard lock(mutex_);
    for (auto& [id, w] : watchers_) to_call.push_back(w);
  }
  for (auto& w : to_call) w();
}

}  // namespace bumprad
