// The jobs that streams are watching, kept up to date from the store's events: each one's
// record and newest preview, shared by all its viewers on this node. A job nobody watches
// costs nothing; the first viewer loads it from the store, the last one lets it go.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "server/job.h"
#include "server/store.h"

namespace bumprad {

class LiveJobs {
 public:
  explicit LiveJobs(Store& store);
  LiveJobs(const LiveJobs&) = delete;
  LiveJobs& operator=(const LiveJobs&) = delete;

  // The job's live view; null when the store has no such job.
  std::shared_ptr<Job> watch(const std::string& id);

 private:
  void refresh(const std::string& id, Job& job);

  Store& store_;
  std::mutex mutex_;
  std::map<std::string, std::weak_ptr<Job>> jobs_;
};

}  // namespace bumprad
