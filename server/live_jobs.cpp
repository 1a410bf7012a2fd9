#include "server/live_jobs.h"

namespace bumprad {

LiveJobs::LiveJobs(Store& store) : store_(store) {
  store_.subscribe([this](const JobEvent& event) {
    if (event.kind != JobEvent::Kind::Changed) return;
    std::shared_ptr<Job> job;
    {
      std::lock_guard lock(mutex_);
      auto it = jobs_.find(event.id);
      if (it == jobs_.end()) return;
      job = it->second.lock();
      if (!job) {
        jobs_.erase(it);
        return;
      }
    }
    refresh(event.id, *job);
  });
}

std::shared_ptr<Job> LiveJobs::watch(const std::string& id) {
  std::shared_ptr<Job> job;
  {
    std::lock_guard lock(mutex_);
    auto& slot = jobs_[id];
    job = slot.lock();
    if (job) return job;
    auto record = store_.find(id);  // in memory or one indexed row
    if (!record) {
      jobs_.erase(id);
      return nullptr;
    }
    job = std::make_shared<Job>(*record);
    slot = job;
  }
  refresh(id, *job);  // the newest preview, and any change before the slot was there
  return job;
}

void LiveJobs::refresh(const std::string& id, Job& job) {
  auto record = store_.find(id);
  if (!record) return;
  const Job::View now = job.view();
  // Events may be handled out of order; a view never goes back.
  if (record->step < now.record.step ||
      (is_finished(now.record.state) && !is_finished(record->state)))
    return;
  if (record->step > now.record.step || !now.preview) {
    auto png = record->step > 0 ? store_.read_step(id, record->step) : std::nullopt;
    if (png) {
      job.publish_step(std::make_shared<const std::string>(std::move(*png)),
                       [&](JobRecord& r) { r = *record; });
      return;
    }
  }
  job.update([&](JobRecord& r) { r = *record; });
}

}  // namespace bumprad
