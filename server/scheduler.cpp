#include "server/scheduler.h"

#include <unistd.h>

#include <cstdio>

namespace bumprad {

std::string process_name() {
  char host[256] = "localhost";
  ::gethostname(host, sizeof host - 1);
  return std::string(host) + ":" + std::to_string(::getpid());
}

Scheduler::Scheduler(Store& store, JobRunner& runner, int workers, std::string name,
                     std::chrono::milliseconds poll)
    : store_(store), runner_(runner), poll_(poll) {
  store_.subscribe([this](const JobEvent& e) { on_event(e); });
  for (int i = 0; i < std::max(1, workers); ++i)
    workers_.emplace_back([this, w = name + "/" + std::to_string(i)] { work(w); });
}

Scheduler::~Scheduler() {
  shutdown();
}

void Scheduler::on_event(const JobEvent& event) {
  std::lock_guard lock(mutex_);
  if (event.kind == JobEvent::Kind::Queued) {
    ++queued_events_;
    wake_.notify_one();
  } else if (event.kind == JobEvent::Kind::CancelRequested) {
    auto it = running_.find(event.id);
    if (it == running_.end()) return;
    it->second->reason = StopReason::Cancelled;
    it->second->stop.request_stop();
  }
}

void Scheduler::shutdown() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && workers_.empty()) return;
    stopping_ = true;
    for (auto& [id, r] : running_) {
      r->reason = StopReason::Shutdown;
      r->stop.request_stop();
    }
  }
  wake_.notify_all();
  for (auto& w : workers_) w.join();
  workers_.clear();
}

void Scheduler::work(const std::string& worker) {
  std::uint64_t seen = 0;
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (stopping_) return;
      seen = queued_events_;
    }
    std::optional<Claim> claim;
    try {
      claim = store_.claim(worker);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: cannot claim a job: %s\n", worker.c_str(), e.what());
    }
    if (!claim) {
      std::unique_lock lock(mutex_);
      wake_.wait_for(lock, poll_, [&] { return stopping_ || queued_events_ != seen; });
      continue;
    }
    auto running = std::make_shared<Running>();
    {
      std::lock_guard lock(mutex_);
      running_[claim->record.id] = running;
      if (stopping_) {
        running->reason = StopReason::Shutdown;
        running->stop.request_stop();
      }
    }
    try {
      runner_.run(worker, *claim, running->stop, running->reason);
    } catch (const std::exception& e) {  // the store failed as the job ended
      std::fprintf(stderr, "job %s: %s\n", claim->record.id.c_str(), e.what());
    }
    std::lock_guard lock(mutex_);
    running_.erase(claim->record.id);
  }
}

}  // namespace bumprad
