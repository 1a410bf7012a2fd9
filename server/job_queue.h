// The bounded job queue and its solver workers: submitted jobs wait their turn, a worker
// solves each with previews at every refinement step, and finished jobs stay on disk
// (within the retention limits) with their perturbed maps, ready to re-texture.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "protocol/api_json.h"
#include "protocol/solution_file.h"
#include "server/job.h"
#include "server/job_store.h"
#include "server/metrics.h"
#include "server/watchdog.h"

namespace bumprad {

struct QueueOptions {
  int workers = 1;
  std::size_t max_queue = 16;  // jobs waiting (not running) before submit refuses
  int keep_steps = 64;         // newest step previews kept per job
  std::size_t max_jobs = 500;  // finished jobs kept; the least recently used go first
  std::uintmax_t max_bytes = std::uintmax_t(4) << 30;  // their files, in all
  std::size_t cached_solutions = 4;  // solved jobs held in memory for re-texturing
  double job_timeout_s = 3600;       // wall clock, from start to the final image; then failed
  ImageFiles files = ImageFiles::refused();
};

class QueueFull : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class JobQueue {
 public:
  // Loads the jobs in `store`: done jobs are served again, queued ones wait again, and
  // those that were running are marked interrupted (re-running them could crash the
  // server again; the client decides). Then starts the workers.
  JobQueue(JobStore& store, Metrics& metrics, Watchdog& watchdog, QueueOptions options);
  ~JobQueue();

  // Throws QueueFull when max_queue jobs are waiting.
  std::shared_ptr<Job> submit(const JobRequest& request);
  std::shared_ptr<Job> find(const std::string& id);
  std::vector<JobRecord> list() const;  // newest first

  enum class Removal { Cancelled, Deleted, Unknown };
  // Cancels a queued or running job (a running one stops within one shot) or deletes a
  // finished one with its files.
  Removal cancel_or_delete(const std::string& id);

  // A done job's solved scene and perturbed map, from memory or its solution file; null if
  // the job is not done. Throws SolutionFileError if the file is damaged.
  std::shared_ptr<const LoadedSolution> solution(const std::string& id);

  Metrics::Gauges gauges() const;
  const ImageFiles& files() const { return options_.files; }
  JobStore& store() { return store_; }

  // Takes no more jobs; running ones stop within one shot and are recorded as interrupted;
  // queued ones stay queued on disk and run after a restart. Waits for the workers.
  void shutdown();

 private:
  void work();
  void run(const std::shared_ptr<Job>& job);
  void finish(const std::shared_ptr<Job>& job, const std::function<void(JobRecord&)>& change);
  void enforce_retention();
  // With mutex_ held: keep a solved job in the cache; drop every trace of a job in memory.
  void remember(const std::string& id, std::shared_ptr<const LoadedSolution> solution);
  void forget(const std::string& id);

  JobStore& store_;
  Metrics& metrics_;
  Watchdog& watchdog_;
  const QueueOptions options_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::map<std::string, std::shared_ptr<Job>> jobs_;
  std::deque<std::shared_ptr<Job>> waiting_;
  std::map<std::string, double> last_used_;      // finished jobs, for LRU eviction
  std::map<std::string, std::uintmax_t> bytes_;  // finished jobs' files
  std::list<std::pair<std::string, std::shared_ptr<const LoadedSolution>>> cache_;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace bumprad
