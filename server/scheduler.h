// The solver workers of one process: each claims the oldest queued job from the store, runs
// it (job_runner.h) and claims the next. They wake when the store says a job was queued, and
// look again every poll period for what no event announced (another node's jobs, expired
// leases). A cancel heard from the store stops the job it names mid-shot.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "server/job_runner.h"
#include "server/store.h"

namespace bumprad {

class Scheduler {
 public:
  // `name` identifies this process's workers to the store ("host:pid"); worker i is
  // "name/i". Subscribes to the store's events and starts the workers.
  Scheduler(Store& store, JobRunner& runner, int workers, std::string name,
            std::chrono::milliseconds poll = std::chrono::milliseconds(1000));
  ~Scheduler();
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  // Claims no more jobs; running ones stop mid-shot and are released to the store.
  // Waits for the workers.
  void shutdown();
  std::size_t workers() const { return workers_.size(); }

 private:
  struct Running {
    std::stop_source stop;
    std::atomic<StopReason> reason{StopReason::None};
  };
  void work(const std::string& worker);
  void on_event(const JobEvent& event);

  Store& store_;
  JobRunner& runner_;
  const std::chrono::milliseconds poll_;

  std::mutex mutex_;
  std::condition_variable wake_;
  std::map<std::string, std::shared_ptr<Running>> running_;  // by job id
  std::uint64_t queued_events_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

// "host:pid", for worker names in the store and logs.
std::string process_name();

}  // namespace bumprad
