// Where jobs live between the API that takes them and the workers that solve them: records,
// scenes, step previews, results, leases, and the events that say a job changed. Two
// implementations: DirectoryStore (one process, a data directory, nothing to install) and
// PostgresStore (any number of API nodes and worker processes sharing one database).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "protocol/job_json.h"
#include "server/retention.h"

namespace bumprad {

// Too many jobs are waiting; the client should retry later (HTTP 429).
class QueueFull : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The store has no room (a full disk or database); its message names what was being
// written, never a server path (HTTP 507).
class StoreFull : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The store does not answer (a database that is down or unreachable); the client should
// retry shortly (HTTP 503). The message never names the store's URL.
class StoreUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An Idempotency-Key reused with another request (HTTP 422).
class KeyReused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class Artifact { Scene, Solution, Png, Exr };

// A job a worker has claimed: it is running under that worker's lease until it ends.
struct Claim {
  JobRecord record;
  std::string scene_json;
};

// A done job's files, stored before its final record says done.
struct Results {
  std::string png, exr, solution;
};

// Something happened to a job. Changed: its record (state, progress, a new step). Queued: a
// worker has something to claim. CancelRequested: the worker running it should stop.
struct JobEvent {
  enum class Kind { Changed, Queued, CancelRequested };
  Kind kind;
  std::string id;
};

struct StoreOptions {
  std::size_t max_queue = 16;  // jobs waiting (not running) before submit refuses
  int keep_steps = 64;         // newest step previews kept per job
  RetentionLimits retention;
};

class Store {
 public:
  virtual ~Store() = default;

  // A new queued job with `record`'s id; or, when `idempotency_key` is not empty and an
  // earlier submission used it, that job (created false). Throws QueueFull, StoreFull, and
  // KeyReused when the key came with another scene.
  struct Submitted {
    JobRecord record;
    bool created = true;
  };
  virtual Submitted submit(const JobRecord& record, std::string_view scene_json,
                           std::string_view idempotency_key) = 0;

  virtual std::optional<JobRecord> find(const std::string& id) = 0;
  virtual std::vector<JobRecord> list() = 0;  // newest first
  virtual std::optional<std::string> read(const std::string& id, Artifact what) = 0;
  virtual std::optional<std::string> read_step(const std::string& id, int step) = 0;
  // A finished job was used (re-textured, downloaded): it is evicted last.
  virtual void touch(const std::string& id) = 0;

  // The oldest queued job, now running under `worker`'s lease; nullopt when none waits.
  virtual std::optional<Claim> claim(const std::string& worker) = 0;
  // A running job's progress, with its new step's preview unless `png` is empty (the newest
  // keep_steps previews are kept; record.step and first_kept_step are set here). Renews the
  // lease, and says whether a cancel was asked for (the event may have come before the
  // worker listened) or the lease was lost: then the worker stops without writing more.
  enum class Lease { Held, CancelRequested, Lost };
  virtual Lease progress(const std::string& worker, JobRecord& record, std::string_view png) = 0;
  // The job's end (done, failed, cancelled): `results` first, when given, then the record.
  // False when the lease was lost (nothing written).
  virtual bool finish(const std::string& worker, const JobRecord& record,
                      const Results* results) = 0;
  // The worker stops (shutdown) without finishing the job. A data directory records it as
  // interrupted; PostgreSQL puts it back in the queue for another worker.
  virtual void release(const std::string& worker, const JobRecord& record) = 0;

  // Cancels a queued or running job (the running one's worker hears of it at once) or
  // deletes a finished one with its files.
  enum class Removal { Cancelled, Deleted, Unknown };
  virtual Removal cancel_or_delete(const std::string& id) = 0;

  // Calls `listener` for every event from now on, on the thread that made it or one of the
  // store's own. It must not block.
  void subscribe(std::function<void(const JobEvent&)> listener);

  struct Counts {
    std::array<std::size_t, 6> jobs_by_state{};  // indexed by JobState
  };
  virtual Counts counts() = 0;
  // Whether the store answers; a line saying why not.
  virtual std::optional<std::string> health() = 0;
  virtual const StoreOptions& options() const = 0;

 protected:
  // Hands `event` to every listener, outside the lock that guards the list.
  void emit(const JobEvent& event);

  // The policy every store applies, written once.
  // The oldest step kept once `step` is the newest: the newest keep_steps of them.
  int first_kept_step(int step) const { return std::max(1, step - options().keep_steps + 1); }
  // Throws QueueFull when `waiting` jobs (queued, or being submitted) already wait.
  void check_queue(std::size_t waiting) const;
  // The answer to a submission whose Idempotency-Key an earlier submission used: the earlier
  // job, not created again, if it came with the same scene; KeyReused if not.
  static Submitted resubmitted(JobRecord earlier, std::string_view earlier_scene,
                               std::string_view scene_json);

 private:
  std::mutex listeners_mutex_;
  std::vector<std::function<void(const JobEvent&)>> listeners_;
};

// A store URL fit for messages and logs: the password of its user (scheme://user:PASSWORD@)
// written as ***.
std::string redacted_url(std::string_view url);

// A fresh random job id (16 hex digits); is_valid_job_id() refuses anything else, so no id
// from a URL can name a path or reach a query unchecked.
std::string new_job_id();
bool is_valid_job_id(std::string_view id);

}  // namespace bumprad
