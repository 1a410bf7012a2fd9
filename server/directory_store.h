// The embedded store (`bumprad serve --data-dir D`, the default): one folder per job holding
// its record, scene, solution with the perturbed map, final images and kept step previews,
// for one process that owns the directory. Every file is written atomically and a job's
// record last, so a crash never leaves half a job that looks whole. The queue, the records
// and the retention bookkeeping live in memory; no file is read or written under its lock.
#pragma once

#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <vector>

#include "server/retention.h"
#include "server/store.h"

namespace bumprad {

class DirectoryStore : public Store {
 public:
  // Creates <data_dir>/jobs if needed and locks the directory for this process (a second
  // server on it is refused with std::runtime_error). Loads the jobs there: done ones are
  // served again, queued ones wait again, and those that were running are recorded as
  // interrupted (re-running them could crash the server again; the client decides).
  DirectoryStore(std::filesystem::path data_dir, StoreOptions options);
  ~DirectoryStore() override;
  DirectoryStore(const DirectoryStore&) = delete;
  DirectoryStore& operator=(const DirectoryStore&) = delete;

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

  // Where a job's files are, for tests that look at the disk.
  std::filesystem::path dir(const std::string& id) const { return jobs_ / id; }
  std::filesystem::path path(const std::string& id, Artifact what) const;
  std::filesystem::path step_path(const std::string& id, int step) const;

 private:
  struct Entry {
    JobRecord record;
    std::string idempotency_key;
    bool cancel_requested = false;
  };
  // Runs a write; file system errors become StoreFull or runtime_error naming `what`.
  void writing(const std::string& what, const std::function<void()>& write) const;
  void save_record(const JobRecord& record) const;
  void load();
  void remove_files(const std::string& id);  // renamed away first, so it vanishes whole
  std::uintmax_t bytes_used(const std::string& id) const;
  // With mutex_ held: the finished jobs past the retention limits, forgotten here; their
  // files are the caller's to remove once the lock is released.
  std::vector<std::string> evict();

  const std::filesystem::path jobs_;
  const StoreOptions options_;
  int lock_fd_ = -1;

  std::mutex mutex_;
  std::map<std::string, Entry> entries_;
  std::deque<std::string> waiting_;
  // Submissions being written, by idempotency key: a retry meanwhile gets the same job.
  std::map<std::string, std::pair<JobRecord, std::string>> pending_keys_;
  std::size_t pending_ = 0;
  Retention retention_;
};

}  // namespace bumprad
