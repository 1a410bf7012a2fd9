// One process's parts put together: its store, the live jobs its streams watch, the
// solution cache, the job runner and its workers, and the API over them. `bumprad serve`
// and `bumprad worker` each run one; tests build one in process.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "server/api.h"
#include "server/job_runner.h"
#include "server/live_jobs.h"
#include "server/metrics.h"
#include "server/postgres_store.h"
#include "server/scheduler.h"
#include "server/solution_cache.h"
#include "server/store.h"
#include "server/watchdog.h"

namespace bumprad {

struct NodeOptions {
  // Empty: the data directory below (one process owns it). "postgresql://...": a database
  // that any number of API nodes and workers share.
  std::string store_url;
  std::filesystem::path data_dir = "bumprad-data";
  int workers = 1;  // solver threads in this process; 0 on an API-only node
  std::size_t cached_solutions = 4;
  StoreOptions store;
  PostgresOptions postgres;
  RunnerOptions runner;
  ApiLimits api;
};

// Opens the store `options` names; throws std::runtime_error saying why it cannot.
std::unique_ptr<Store> open_store(const NodeOptions& options);

class Node {
 public:
  explicit Node(const NodeOptions& options);
  ~Node() { shutdown(); }
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  // Claims no more jobs; running ones stop mid-shot and go back to the store.
  void shutdown() {
    if (scheduler) scheduler->shutdown();
  }

  Metrics metrics;
  Watchdog watchdog;
  const std::unique_ptr<Store> store;
  LiveJobs live;
  SolutionCache solutions;
  JobRunner runner;
  const std::unique_ptr<Scheduler> scheduler;  // null without workers
  Api api;
};

}  // namespace bumprad
