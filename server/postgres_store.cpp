#include "server/postgres_store.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include <pqxx/pqxx>

#include "common/stopwatch.h"
#include "server/migrations.h"

namespace bumprad {
namespace {

constexpr const char* kChannel = "bumprad";
// Serialises schema migrations between processes starting at once.
constexpr long long kMigrationLock = 0x62756d70726164;  // "bumprad"

// A job's state in the columns and in the record stay the same word.
std::string state_word(JobState state) {
  return std::string(to_string(state));
}

pqxx::binarystring bytes_param(std::string_view bytes) {
  return pqxx::binarystring(bytes.data(), bytes.size());
}

std::string bytes_of(const pqxx::field& field) {
  return pqxx::binarystring(field).str();
}

// What the database said, without the URL (it may hold a password).
[[noreturn]] void unreachable(const std::exception& e) {
  throw StoreUnavailable(std::string("the job database is unreachable: ") + e.what());
}

}  // namespace

// Connections for the store's calls, one per call at a time: pqxx connections are not
// shared between threads. A broken one is dropped, and the next call connects anew.
class PostgresStore::Pool {
 public:
  explicit Pool(std::string url) : url_(std::move(url)) {}

  class Lease {
   public:
    Lease(Pool& pool, std::unique_ptr<pqxx::connection> c) : pool_(pool), c_(std::move(c)) {}
    ~Lease() { pool_.give_back(std::move(c_)); }
    pqxx::connection& operator*() { return *c_; }

   private:
    Pool& pool_;
    std::unique_ptr<pqxx::connection> c_;
  };

  Lease take() {
    {
      std::lock_guard lock(mutex_);
      if (!idle_.empty()) {
        auto c = std::move(idle_.back());
        idle_.pop_back();
        return Lease(*this, std::move(c));
      }
    }
    try {
      return Lease(*this, std::make_unique<pqxx::connection>(url_));
    } catch (const pqxx::broken_connection& e) {
      unreachable(e);
    }
  }

  const std::string& url() const { return url_; }

 private:
  void give_back(std::unique_ptr<pqxx::connection> c) {
    if (!c || !c->is_open()) return;
    std::lock_guard lock(mutex_);
    if (idle_.size() < 16) idle_.push_back(std::move(c));
  }

  const std::string url_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<pqxx::connection>> idle_;
};

namespace {

// Runs `body` in a transaction on a pooled connection. A connection that broke (an idle one
// from before a database restart, or one cut midway) is dropped and the body runs once more
// on a new one: nothing of it was committed. If that fails too, the store is unavailable.
// A connection lost during the commit itself leaves the transaction in doubt: the store is
// unavailable too, and whoever retries must find a write that did land harmless (every
// write here is: a step is stored once, a finish or a release of a job no longer running
// matches nothing).
template <typename Pool, typename Body>
auto in_transaction(Pool& pool, Body&& body) {
  for (int attempt = 0;; ++attempt) {
    auto lease = pool.take();
    try {
      pqxx::work tx(*lease);
      if constexpr (std::is_void_v<decltype(body(tx))>) {
        body(tx);
        tx.commit();
        return;
      } else {
        auto result = body(tx);
        tx.commit();
        return result;
      }
    } catch (const pqxx::broken_connection& e) {
      (*lease).disconnect();
      if (attempt > 0) unreachable(e);
    } catch (const pqxx::in_doubt_error& e) {
      (*lease).disconnect();
      unreachable(e);
    }
  }
}

void notify(pqxx::work& tx, std::string_view kind, const std::string& id) {
  tx.exec_params("SELECT pg_notify($1, $2)", kChannel, std::string(kind) + " " + id);
}

}  // namespace

int PostgresStore::schema_version() {
  return int(schema_migrations().size());
}

PostgresStore::PostgresStore(const std::string& url, StoreOptions options, PostgresOptions pg)
    : options_(options), pg_(pg), url_(url), pool_(std::make_unique<Pool>(url)) {
  in_transaction(*pool_, [&](pqxx::work& tx) {
    tx.exec_params("SELECT pg_advisory_xact_lock($1)", kMigrationLock);
    tx.exec0(
        "CREATE TABLE IF NOT EXISTS bumprad_schema (version integer PRIMARY KEY, "
        "applied timestamptz NOT NULL DEFAULT now())");
    const int have = tx.exec1("SELECT coalesce(max(version), 0) FROM bumprad_schema")[0].as<int>();
    const auto migrations = schema_migrations();
    if (have > int(migrations.size()))
      throw std::runtime_error("the job database has schema version " + std::to_string(have) +
                               "; this build knows up to " + std::to_string(migrations.size()) +
                               " (upgrade bumprad)");
    for (int v = have; v < int(migrations.size()); ++v) {
      tx.exec0(std::string(migrations[std::size_t(v)]));
      tx.exec_params("INSERT INTO bumprad_schema (version) VALUES ($1)", v + 1);
      std::fprintf(stderr, "job database: migrated to schema version %d\n", v + 1);
    }
  });
  listener_ = std::thread([this] { listen(); });
}

PostgresStore::~PostgresStore() {
  stopping_ = true;
  if (listener_.joinable()) listener_.join();
}

void PostgresStore::listen() {
  struct Receiver : pqxx::notification_receiver {
    Receiver(pqxx::connection& c, PostgresStore& s)
        : notification_receiver(c, kChannel), store(s) {}
    void operator()(const std::string& payload, int) override {
      const auto space = payload.find(' ');
      if (space == std::string::npos) return;
      const std::string kind = payload.substr(0, space);
      JobEvent event{JobEvent::Kind::Changed, payload.substr(space + 1)};
      if (kind == "queued") event.kind = JobEvent::Kind::Queued;
      if (kind == "cancel") event.kind = JobEvent::Kind::CancelRequested;
      store.emit(event);
    }
    PostgresStore& store;
  };
  double backoff = 0.1;
  while (!stopping_) {
    try {
      pqxx::connection c(url_);
      Receiver receiver(c, *this);
      c.get_notifs();
      backoff = 0.1;
      // Whatever was announced while not listening: workers look for it.
      emit({JobEvent::Kind::Queued, ""});
      while (!stopping_) c.await_notification(0, 200'000);
    } catch (const std::exception& e) {
      if (stopping_) break;
      std::fprintf(stderr, "job database: listening failed (%s); again in %.1f s\n", e.what(),
                   backoff);
      std::this_thread::sleep_for(std::chrono::duration<double>(backoff));
      backoff = std::min(5.0, backoff * 2);
    }
  }
}

Store::Submitted PostgresStore::submit(const JobRecord& record, std::string_view scene_json,
                                       std::string_view idempotency_key) {
  return in_transaction(*pool_, [&](pqxx::work& tx) -> Submitted {
    if (!idempotency_key.empty()) {
      pqxx::result earlier =
          tx.exec_params("SELECT record, scene_json FROM jobs WHERE idempotency_key = $1",
                         std::string(idempotency_key));
      if (!earlier.empty())
        return resubmitted(job_from_json(earlier[0][0].as<std::string>()),
                           earlier[0][1].as<std::string>(), scene_json);
    }
    // Counted without a lock, so nodes submitting at the same moment may pass the limit by
    // a few: it bounds the backlog, not an invariant.
    const auto waiting =
        tx.exec1("SELECT count(*) FROM jobs WHERE state = 'queued'")[0].as<std::size_t>();
    check_queue(waiting);
    pqxx::result inserted = tx.exec_params(
        "INSERT INTO jobs (id, state, record, created, scene_json, idempotency_key) "
        "VALUES ($1, 'queued', $2, $3, $4, nullif($5, '')) "
        "ON CONFLICT (idempotency_key) DO NOTHING RETURNING id",
        record.id, job_to_json(record), record.created, std::string(scene_json),
        std::string(idempotency_key));
    if (inserted.empty()) {  // the same key, committed by another node a moment ago
      pqxx::row earlier =
          tx.exec_params1("SELECT record, scene_json FROM jobs WHERE idempotency_key = $1",
                          std::string(idempotency_key));
      return resubmitted(job_from_json(earlier[0].as<std::string>()), earlier[1].as<std::string>(),
                         scene_json);
    }
    notify(tx, "queued", record.id);
    return {record, true};
  });
}

std::optional<JobRecord> PostgresStore::find(const std::string& id) {
  return in_transaction(*pool_, [&](pqxx::work& tx) -> std::optional<JobRecord> {
    pqxx::result r = tx.exec_params("SELECT record FROM jobs WHERE id = $1", id);
    if (r.empty()) return std::nullopt;
    return job_from_json(r[0][0].as<std::string>());
  });
}

std::vector<JobRecord> PostgresStore::list() {
  return in_transaction(*pool_, [&](pqxx::work& tx) {
    std::vector<JobRecord> out;
    for (const auto& row : tx.exec("SELECT record FROM jobs ORDER BY created DESC"))
      out.push_back(job_from_json(row[0].as<std::string>()));
    return out;
  });
}

std::optional<std::string> PostgresStore::read(const std::string& id, Artifact what) {
  const char* query = "";
  switch (what) {
    case Artifact::Scene:
      query = "SELECT scene_json FROM jobs WHERE id = $1";
      break;
    case Artifact::Solution:
      query = "SELECT solution FROM results WHERE job_id = $1";
      break;
    case Artifact::Png:
      query = "SELECT png FROM results WHERE job_id = $1";
      break;
    case Artifact::Exr:
      query = "SELECT exr FROM results WHERE job_id = $1";
      break;
  }
  return in_transaction(*pool_, [&](pqxx::work& tx) -> std::optional<std::string> {
    pqxx::result r = tx.exec_params(query, id);
    if (r.empty()) return std::nullopt;
    return what == Artifact::Scene ? r[0][0].as<std::string>() : bytes_of(r[0][0]);
  });
}

std::optional<std::string> PostgresStore::read_step(const std::string& id, int step) {
  return in_transaction(*pool_, [&](pqxx::work& tx) -> std::optional<std::string> {
    pqxx::result r =
        tx.exec_params("SELECT png FROM steps WHERE job_id = $1 AND step = $2", id, step);
    if (r.empty()) return std::nullopt;
    return bytes_of(r[0][0]);
  });
}

void PostgresStore::touch(const std::string& id) {
  in_transaction(*pool_, [&](pqxx::work& tx) {
    tx.exec_params(
        "UPDATE jobs SET last_used = $2 WHERE id = $1 AND state NOT IN ('queued', 'running')", id,
        unix_now());
  });
}

std::optional<Claim> PostgresStore::claim(const std::string& worker) {
  return in_transaction(*pool_, [&](pqxx::work& tx) -> std::optional<Claim> {
    // Jobs whose worker stopped renewing: cancelled if that was asked, failed after
    // max_attempts claims, otherwise back in the queue.
    for (const auto& row : tx.exec_params(
             "SELECT id, record, attempts, cancel_requested FROM jobs WHERE state = 'running' "
             "AND lease_until < now() FOR UPDATE SKIP LOCKED")) {
      JobRecord r = job_from_json(row[1].as<std::string>());
      const int attempts = row[2].as<int>();
      if (row[3].as<bool>()) {
        r.state = JobState::Cancelled;
      } else if (attempts >= pg_.max_attempts) {
        r.state = JobState::Failed;
        r.error = "its worker stopped answering on each of " + std::to_string(attempts) +
                  " attempts (the job may crash the solver)";
      } else {
        r.state = JobState::Queued;
        std::fprintf(stderr, "job %s: its worker's lease expired; queued again\n", r.id.c_str());
      }
      if (is_finished(r.state)) r.finished = unix_now();
      tx.exec_params(
          "UPDATE jobs SET state = $2, record = $3, worker = NULL, lease_until = NULL, "
          "last_used = $4 WHERE id = $1",
          r.id, state_word(r.state), job_to_json(r), r.finished);
      notify(tx, r.state == JobState::Queued ? "queued" : "changed", r.id);
    }
    pqxx::result next = tx.exec(
        "SELECT id, record, scene_json FROM jobs WHERE state = 'queued' ORDER BY created "
        "LIMIT 1 FOR UPDATE SKIP LOCKED");
    if (next.empty()) return std::nullopt;
    Claim claim{job_from_json(next[0][1].as<std::string>()), next[0][2].as<std::string>()};
    claim.record.state = JobState::Running;
    claim.record.started = unix_now();
    claim.record.error.clear();
    tx.exec_params(
        "UPDATE jobs SET state = 'running', record = $2, worker = $3, attempts = attempts + 1, "
        "lease_until = now() + make_interval(secs => $4) WHERE id = $1",
        claim.record.id, job_to_json(claim.record), worker, pg_.lease_s);
    notify(tx, "changed", claim.record.id);
    return claim;
  });
}

Store::Lease PostgresStore::progress(const std::string& worker, JobRecord& record,
                                     std::string_view png) {
  JobRecord next = record;
  if (!png.empty()) {
    next.step = record.step + 1;
    next.first_kept_step = first_kept_step(next.step);
  }
  const Lease lease = in_transaction(*pool_, [&](pqxx::work& tx) {
    pqxx::result held = tx.exec_params(
        "UPDATE jobs SET record = $3, lease_until = now() + make_interval(secs => $4) "
        "WHERE id = $1 AND worker = $2 AND state = 'running' RETURNING cancel_requested",
        next.id, worker, job_to_json(next), pg_.lease_s);
    if (held.empty()) return Lease::Lost;
    if (!png.empty()) {
      tx.exec_params(
          "INSERT INTO steps (job_id, step, png) VALUES ($1, $2, $3) "
          "ON CONFLICT (job_id, step) DO UPDATE SET png = excluded.png",
          next.id, next.step, bytes_param(png));
      tx.exec_params("DELETE FROM steps WHERE job_id = $1 AND step < $2", next.id,
                     next.first_kept_step);
    }
    notify(tx, "changed", next.id);
    return held[0][0].as<bool>() ? Lease::CancelRequested : Lease::Held;
  });
  if (lease != Lease::Lost) record = next;
  return lease;
}

bool PostgresStore::finish(const std::string& worker, const JobRecord& final_record,
                           const Results* results) {
  JobRecord r = final_record;
  r.finished = unix_now();
  const bool done = in_transaction(*pool_, [&](pqxx::work& tx) {
    pqxx::result held = tx.exec_params(
        "UPDATE jobs SET state = $3, record = $4, worker = NULL, lease_until = NULL, "
        "last_used = $5 WHERE id = $1 AND worker = $2 AND state = 'running' RETURNING id",
        r.id, worker, state_word(r.state), job_to_json(r), r.finished);
    if (held.empty()) return false;
    if (results)
      tx.exec_params("INSERT INTO results (job_id, png, exr, solution) VALUES ($1, $2, $3, $4)",
                     r.id, bytes_param(results->png), bytes_param(results->exr),
                     bytes_param(results->solution));
    tx.exec_params(
        "UPDATE jobs SET bytes = length(scene_json) + "
        "coalesce((SELECT sum(length(png)) FROM steps WHERE job_id = $1), 0) + "
        "coalesce((SELECT length(png) + length(exr) + length(solution) FROM results "
        "WHERE job_id = $1), 0) WHERE id = $1",
        r.id);
    notify(tx, "changed", r.id);
    return true;
  });
  if (done && unix_now() >= next_sweep_) {
    next_sweep_ = unix_now() + pg_.retention_interval_s;
    sweep();
  }
  return done;
}

void PostgresStore::sweep() {
  // Retention: the least recently used finished jobs past either limit. The query reads
  // every kept job, hence at most one sweep per retention_interval_s, not one per finish.
  in_transaction(*pool_, [&](pqxx::work& tx) {
    tx.exec_params(
        "DELETE FROM jobs WHERE id IN (SELECT id FROM (SELECT id, "
        "row_number() OVER (ORDER BY last_used DESC) AS n, "
        "sum(bytes) OVER (ORDER BY last_used DESC) AS total FROM jobs "
        "WHERE state NOT IN ('queued', 'running')) kept WHERE n > $1 OR total > $2)",
        static_cast<long long>(options_.retention.max_jobs),
        static_cast<long long>(
            std::min<std::uintmax_t>(options_.retention.max_bytes, std::uintmax_t(1) << 62)));
  });
}

void PostgresStore::release(const std::string& worker, const JobRecord& record) {
  JobRecord r = record;
  r.state = JobState::Queued;
  in_transaction(*pool_, [&](pqxx::work& tx) {
    // A shutdown is not the job's fault: the attempt is not counted.
    pqxx::result held = tx.exec_params(
        "UPDATE jobs SET state = 'queued', record = $3, worker = NULL, lease_until = NULL, "
        "attempts = greatest(attempts - 1, 0) "
        "WHERE id = $1 AND worker = $2 AND state = 'running' RETURNING id",
        r.id, worker, job_to_json(r));
    if (!held.empty()) notify(tx, "queued", r.id);
  });
  std::fprintf(stderr, "job %s: released to the queue (this worker is stopping)\n", r.id.c_str());
}

Store::Removal PostgresStore::cancel_or_delete(const std::string& id) {
  return in_transaction(*pool_, [&](pqxx::work& tx) {
    pqxx::result found =
        tx.exec_params("SELECT state, record FROM jobs WHERE id = $1 FOR UPDATE", id);
    if (found.empty()) return Removal::Unknown;
    const std::string state = found[0][0].as<std::string>();
    if (state == "queued") {
      JobRecord r = job_from_json(found[0][1].as<std::string>());
      r.state = JobState::Cancelled;
      r.finished = unix_now();
      tx.exec_params(
          "UPDATE jobs SET state = 'cancelled', record = $2, last_used = $3 WHERE id = $1", id,
          job_to_json(r), r.finished);
      notify(tx, "changed", id);
      return Removal::Cancelled;
    }
    if (state == "running") {  // its worker records it as cancelled
      tx.exec_params("UPDATE jobs SET cancel_requested = true WHERE id = $1", id);
      notify(tx, "cancel", id);
      return Removal::Cancelled;
    }
    tx.exec_params("DELETE FROM jobs WHERE id = $1", id);
    return Removal::Deleted;
  });
}

Store::Counts PostgresStore::counts() {
  return in_transaction(*pool_, [&](pqxx::work& tx) {
    Counts c;
    for (const auto& row : tx.exec("SELECT state, count(*) FROM jobs GROUP BY state"))
      if (auto s = job_state_from(row[0].as<std::string>()))
        c.jobs_by_state[std::size_t(*s)] = row[1].as<std::size_t>();
    return c;
  });
}

std::optional<std::string> PostgresStore::health() {
  try {
    in_transaction(*pool_, [](pqxx::work& tx) { tx.exec("SELECT 1"); });
    return std::nullopt;
  } catch (const std::exception& e) {
    return std::string(e.what());
  }
}

}  // namespace bumprad
