// One job's live state on this node, shared by the connections that watch it: its record,
// its newest preview, and whom to wake when they change (live_jobs.h keeps it current).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "protocol/api_json.h"

namespace bumprad {

class Job {
 public:
  explicit Job(JobRecord record) : record_(std::move(record)) {}

  struct View {
    JobRecord record;
    std::shared_ptr<const std::string> preview;  // PNG of record.step; null before step 1
  };
  View view() const;
  JobRecord record() const { return view().record; }

  // Applies `change` to the record under the lock, then wakes the watchers.
  void update(const std::function<void(JobRecord&)>& change);
  // A new refinement step and its preview, then wakes the watchers.
  void publish_step(std::shared_ptr<const std::string> png,
                    const std::function<void(JobRecord&)>& change);

  // Watchers are called on the thread that changed the job, outside the lock: they should
  // only post to their own executor. Viewers read view() then, so a slow one sees only the
  // newest step and the worker never waits for it.
  using Watcher = std::function<void()>;
  int watch(Watcher watcher);
  void unwatch(int id);

 private:
  void wake();

  mutable std::mutex mutex_;
  JobRecord record_;
  std::shared_ptr<const std::string> preview_;
  std::map<int, Watcher> watchers_;
  int next_watcher_ = 0;
};

}  // namespace bumprad
