// The shared store (`--store postgresql://...`): jobs, scenes, step previews, results and
// leases in PostgreSQL, so any number of API nodes and worker processes serve and solve the
// same jobs with no shared filesystem. Workers claim with FOR UPDATE SKIP LOCKED under a
// lease that every refinement step renews; a job whose worker vanished runs again
// elsewhere, up to max_attempts. Events travel by LISTEN/NOTIFY. The schema's migrations
// (server/migrations/) are applied at start.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "server/store.h"

namespace bumprad {

struct PostgresOptions {
  double lease_s = 30;   // a worker that renews nothing for this long loses its job
  int max_attempts = 3;  // claims of one job before it fails for good
  // Finished jobs past the retention limits go in a sweep after a finish, at most this often
  // per process (a sweep reads every kept job).
  double retention_interval_s = 1;
};

class PostgresStore : public Store {
 public:
  // Connects, applies the migrations this build has and the database lacks, and starts
  // listening for events. Throws std::runtime_error saying what failed (never the password).
  PostgresStore(const std::string& url, StoreOptions options, PostgresOptions pg = {});
  ~PostgresStore() override;
  PostgresStore(const PostgresStore&) = delete;
  PostgresStore& operator=(const PostgresStore&) = delete;

  Submitted submit(const JobRecord& record, std::string_view scene_json,
                   std::string_view idempotency_key) override;
  std::optional<JobRecord> find(const std::string& id) override;
  std::vector<JobRecord> list() override;
  std::optional<std::string> read(const std::string& id, Artifact what) override;
  std::optional<std::string> read_step(const std::string& id, int step) override;
  void touch(const std::string& id) override;
  std::optional<Claim> claim(const std::string& worker) override;
  Lease progress(const std::string& worker, JobRecord& record, std::string_view png) override;
  bool finish(const std::string& worker, const JobRecord& record, const Results* results) override;
  void release(const std::string& worker, const JobRecord& record) override;
  Removal cancel_or_delete(const std::string& id) override;
  Counts counts() override;
  std::optional<std::string> health() override;
  const StoreOptions& options() const override { return options_; }

  // The schema version this build migrates to.
  static int schema_version();

 private:
  class Pool;
  void listen();
  void sweep();

  const StoreOptions options_;
  const PostgresOptions pg_;
  const std::string url_;
  std::unique_ptr<Pool> pool_;

  std::atomic<double> next_sweep_{0};  // unix time
  std::atomic<bool> stopping_{false};
  std::thread listener_;
};

}  // namespace bumprad
