// Runs one claimed job: parses its scene, solves it with a draft preview at refinement
// steps (renewing the worker's lease at every step), renders the final image and stores
// the results. Knows nothing of where the store keeps them or who watches.
#pragma once

#include <atomic>
#include <stop_token>
#include <string>

#include "protocol/scene_json.h"
#include "server/metrics.h"
#include "server/store.h"
#include "server/watchdog.h"

namespace bumprad {

struct RunnerOptions {
  double job_timeout_s = 3600;  // wall clock, from start to the final image; then failed
  ImageFiles files = ImageFiles::refused();
};

// Why a running job was told to stop, set before its stop source is stopped.
enum class StopReason { None, Cancelled, Shutdown };

class JobRunner {
 public:
  JobRunner(Store& store, Metrics& metrics, Watchdog& watchdog, RunnerOptions options)
      : store_(store), metrics_(metrics), watchdog_(watchdog), options_(std::move(options)) {}

  // Returns when the job has ended (done, failed, cancelled), was released at shutdown, or
  // its lease was lost. `stop` ends it mid-shot; `reason` says why.
  void run(const std::string& worker, const Claim& claim, std::stop_source stop,
           const std::atomic<StopReason>& reason);

  const RunnerOptions& options() const { return options_; }

 private:
  class Attempt;
  Store& store_;
  Metrics& metrics_;
  Watchdog& watchdog_;
  const RunnerOptions options_;
};

}  // namespace bumprad
