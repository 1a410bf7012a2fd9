#include "server/directory_store.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <system_error>

#include "common/atomic_file.h"
#include "common/stopwatch.h"

namespace bumprad {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kRecord = "job.json";
constexpr std::string_view kKey = "idempotency-key";
constexpr std::string_view kRemoving = ".removing-";

// Temporary files of atomic writes (common/atomic_file.cpp) are ".NAME.tmp-PID-N.EXT".
bool is_temporary(const std::string& name) {
  return name.starts_with('.') && name.find(".tmp-") != std::string::npos;
}

std::optional<std::string> read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// Removes the temporary files a crash left in a job's folder, and brings the record's step
// range up to the step previews on disk (the record is rewritten only when the job starts
// and ends).
void scan_files(const fs::path& dir, JobRecord& record) {
  std::error_code ignored;
  int first = 0, last = 0;
  for (const fs::path& folder : {dir, dir / "steps"})
    for (auto it = fs::directory_iterator(folder, ignored); it != fs::directory_iterator();
         it.increment(ignored)) {
      const std::string name = it->path().filename().string();
      if (is_temporary(name)) {
        fs::remove(it->path(), ignored);
        continue;
      }
      if (folder == dir || !name.ends_with(".png")) continue;
      int step = std::atoi(name.c_str());
      if (step <= 0) continue;
      first = first == 0 ? step : std::min(first, step);
      last = std::max(last, step);
    }
  if (last > record.step) {
    record.step = last;
    record.first_kept_step = first;
  }
}

void log_state(const JobRecord& j) {
  std::fprintf(stderr, "job %s %s (%s, %d/%d shots)%s%s\n", j.id.c_str(),
               std::string(to_string(j.state)).c_str(), j.scene_name.c_str(), j.shots, j.max_shots,
               j.error.empty() ? "" : ": ", j.error.c_str());
}

}  // namespace

DirectoryStore::DirectoryStore(fs::path data_dir, StoreOptions options)
    : jobs_(data_dir / "jobs"), options_(options), retention_(options.retention) {
  fs::create_directories(jobs_);
  fs::path lock = data_dir / "lock";
  lock_fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0 || ::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    if (lock_fd_ >= 0) ::close(lock_fd_);
    throw std::runtime_error(data_dir.string() +
                             " is in use by another bumprad serve (or cannot be locked)");
  }
  load();
}

DirectoryStore::~DirectoryStore() {
  ::close(lock_fd_);
}

fs::path DirectoryStore::path(const std::string& id, Artifact what) const {
  switch (what) {
    case Artifact::Scene:
      return dir(id) / "scene.json";
    case Artifact::Solution:
      return dir(id) / "solution.bumprad";
    case Artifact::Png:
      return dir(id) / "image.png";
    case Artifact::Exr:
      return dir(id) / "image.exr";
  }
  return {};
}

fs::path DirectoryStore::step_path(const std::string& id, int step) const {
  return dir(id) / "steps" / (std::to_string(step) + ".png");
}

void DirectoryStore::writing(const std::string& what, const std::function<void()>& write) const {
  try {
    write();
  } catch (const std::system_error& e) {
    if (e.code() == std::errc::no_space_on_device || e.code().value() == EDQUOT)
      throw StoreFull("the server's disk is full (writing " + what + "); try again later");
    throw std::runtime_error("cannot write " + what + ": " + e.code().message());
  }
}

void DirectoryStore::save_record(const JobRecord& record) const {
  writing("the job's record",
          [&] { write_file_atomically(dir(record.id) / kRecord, job_to_json(record)); });
  log_state(record);
}

void DirectoryStore::load() {
  struct Loaded {
    JobRecord record;
    std::string key;
  };
  std::vector<Loaded> loaded;
  for (const auto& entry : fs::directory_iterator(jobs_)) {
    std::string name = entry.path().filename().string();
    std::error_code ignored;
    if (name.starts_with(kRemoving)) {
      fs::remove_all(entry.path(), ignored);
      continue;
    }
    if (!is_valid_job_id(name)) continue;  // not ours: leave it alone
    auto record = read_file(entry.path() / kRecord);
    try {
      if (record && fs::exists(path(name, Artifact::Scene))) {
        Loaded l{job_from_json(*record), read_file(entry.path() / kKey).value_or("")};
        scan_files(entry.path(), l.record);
        loaded.push_back(std::move(l));
        continue;
      }
    } catch (const std::exception&) {
    }
    remove_files(name);  // a submit cut short
  }
  std::sort(loaded.begin(), loaded.end(),
            [](const auto& a, const auto& b) { return a.record.created < b.record.created; });
  // A record that cannot be rewritten now (a full disk) is corrected in memory, and again
  // at the next start: the server starts all the same.
  auto correct = [&](const JobRecord& r) {
    try {
      save_record(r);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "job %s: %s\n", r.id.c_str(), e.what());
    }
  };
  for (auto& [r, key] : loaded) {
    if (r.state == JobState::Running) {
      r.state = JobState::Interrupted;
      r.finished = unix_now();
      r.error = "the server stopped while this job was running; submit it again";
      correct(r);
    }
    if (r.state == JobState::Done &&
        !(fs::exists(path(r.id, Artifact::Solution)) && fs::exists(path(r.id, Artifact::Png)))) {
      r.state = JobState::Failed;
      r.error = "the job's files were lost from the data directory";
      correct(r);
    }
    if (r.state == JobState::Queued)
      waiting_.push_back(r.id);
    else
      retention_.keep(r.id, r.finished, bytes_used(r.id));
    entries_[r.id] = {r, key};
  }
  if (!loaded.empty())
    std::fprintf(stderr, "loaded %zu jobs from the data directory (%zu queued)\n", loaded.size(),
                 waiting_.size());
  for (const std::string& id : evict()) remove_files(id);
}

Store::Submitted DirectoryStore::submit(const JobRecord& record, std::string_view scene_json,
                                        std::string_view idempotency_key) {
  const std::string key(idempotency_key);
  std::optional<JobRecord> earlier;
  {
    std::lock_guard lock(mutex_);
    if (!key.empty()) {
      auto pending = pending_keys_.find(key);
      if (pending != pending_keys_.end())
        return resubmitted(pending->second.first, pending->second.second, scene_json);
      for (const auto& [id, e] : entries_)
        if (e.idempotency_key == key) earlier = e.record;
    }
    if (!earlier) {
      check_queue(waiting_.size() + pending_);
      ++pending_;
      if (!key.empty()) pending_keys_[key] = {record, std::string(scene_json)};
    }
  }
  if (earlier)
    return resubmitted(*earlier, read(earlier->id, Artifact::Scene).value_or(""), scene_json);
  auto done_pending = [&] {
    std::lock_guard lock(mutex_);
    --pending_;
    pending_keys_.erase(key);
  };
  try {
    writing("the job's folder", [&] { fs::create_directories(dir(record.id) / "steps"); });
    writing("the job's scene",
            [&] { write_file_atomically(path(record.id, Artifact::Scene), scene_json); });
    if (!key.empty())
      writing("the job's key", [&] { write_file_atomically(dir(record.id) / kKey, key); });
    save_record(record);
  } catch (...) {
    remove_files(record.id);
    done_pending();
    throw;
  }
  {  // in one step, so a retry always finds the key: pending, or on the job
    std::lock_guard lock(mutex_);
    --pending_;
    pending_keys_.erase(key);
    entries_[record.id] = {record, key};
    waiting_.push_back(record.id);
  }
  emit({JobEvent::Kind::Queued, record.id});
  return {record, true};
}

std::optional<JobRecord> DirectoryStore::find(const std::string& id) {
  std::lock_guard lock(mutex_);
  auto it = entries_.find(id);
  if (it == entries_.end()) return std::nullopt;
  return it->second.record;
}

std::vector<JobRecord> DirectoryStore::list() {
  std::vector<JobRecord> out;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, e] : entries_) out.push_back(e.record);
  }
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return a.created > b.created; });
  return out;
}

std::optional<std::string> DirectoryStore::read(const std::string& id, Artifact what) {
  if (!is_valid_job_id(id)) return std::nullopt;
  return read_file(path(id, what));
}

std::optional<std::string> DirectoryStore::read_step(const std::string& id, int step) {
  if (!is_valid_job_id(id)) return std::nullopt;
  return read_file(step_path(id, step));
}

void DirectoryStore::touch(const std::string& id) {
  std::lock_guard lock(mutex_);
  retention_.touch(id, unix_now());
}

std::optional<Claim> DirectoryStore::claim(const std::string&) {
  Claim claim;
  {
    std::lock_guard lock(mutex_);
    if (waiting_.empty()) return std::nullopt;
    claim.record = entries_.at(waiting_.front()).record;
    waiting_.pop_front();
  }
  claim.record.state = JobState::Running;
  claim.record.started = unix_now();
  // On disk before anyone is told: a crash from here on finds the job interrupted.
  try {
    save_record(claim.record);
    auto scene = read(claim.record.id, Artifact::Scene);
    if (!scene) throw std::runtime_error("the job's scene file is missing");
    claim.scene_json = std::move(*scene);
  } catch (const std::exception& e) {
    JobRecord failed = claim.record;
    failed.state = JobState::Failed;
    failed.error = e.what();
    finish("", failed, nullptr);
    return this->claim("");
  }
  {
    std::lock_guard lock(mutex_);
    entries_.at(claim.record.id).record = claim.record;
  }
  emit({JobEvent::Kind::Changed, claim.record.id});
  return claim;
}

Store::Lease DirectoryStore::progress(const std::string&, JobRecord& record, std::string_view png) {
  std::optional<JobRecord> now = find(record.id);
  if (!now) return Lease::Lost;
  if (!png.empty()) {
    const int step = now->step + 1;
    writing("step " + std::to_string(step),
            [&] { write_file_atomically(step_path(record.id, step), png); });
    const int first = first_kept_step(step);
    std::error_code ignored;
    for (int s = std::max(1, now->first_kept_step); s < first; ++s)
      fs::remove(step_path(record.id, s), ignored);
    record.step = step;
    record.first_kept_step = first;
  }
  bool cancel;
  {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(record.id);
    if (it == entries_.end()) return Lease::Lost;
    it->second.record = record;
    cancel = it->second.cancel_requested;
  }
  emit({JobEvent::Kind::Changed, record.id});
  return cancel ? Lease::CancelRequested : Lease::Held;
}

bool DirectoryStore::finish(const std::string&, const JobRecord& final_record,
                            const Results* results) {
  JobRecord r = final_record;
  r.finished = unix_now();
  try {
    if (results) {
      writing("the job's image.png",
              [&] { write_file_atomically(path(r.id, Artifact::Png), results->png); });
      writing("the job's image.exr",
              [&] { write_file_atomically(path(r.id, Artifact::Exr), results->exr); });
      writing("the job's solution",
              [&] { write_file_atomically(path(r.id, Artifact::Solution), results->solution); });
    }
    save_record(r);  // last: the job is whole on disk before it says so
  } catch (const std::exception& e) {
    r.state = JobState::Failed;
    r.error = std::string("cannot write the job's files: ") + e.what();
    log_state(r);
  }
  // Counted before the job shows as finished: a DELETE can only come after that.
  const std::uintmax_t bytes = bytes_used(r.id);
  std::vector<std::string> evicted;
  {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(r.id);
    if (it == entries_.end()) return false;
    it->second.record = r;
    retention_.keep(r.id, r.finished, bytes);
    evicted = evict();
  }
  emit({JobEvent::Kind::Changed, r.id});
  for (const std::string& id : evicted) {
    remove_files(id);
    std::fprintf(stderr, "job %s evicted (retention limits)\n", id.c_str());
  }
  return true;
}

void DirectoryStore::release(const std::string& worker, const JobRecord& record) {
  JobRecord r = record;
  r.state = JobState::Interrupted;
  r.error = "the server shut down while this job was running";
  finish(worker, r, nullptr);
}

Store::Removal DirectoryStore::cancel_or_delete(const std::string& id) {
  JobRecord record;
  {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(id);
    if (it == entries_.end()) return Removal::Unknown;
    record = it->second.record;
    auto waiting = std::find(waiting_.begin(), waiting_.end(), id);
    if (record.state == JobState::Queued && waiting == waiting_.end())
      record.state = JobState::Running;  // being claimed: its worker will hear of it
    if (record.state == JobState::Queued) {
      waiting_.erase(waiting);
    } else if (record.state == JobState::Running) {
      it->second.cancel_requested = true;
    } else if (is_finished(record.state)) {
      entries_.erase(it);
      retention_.forget(id);
    }
  }
  switch (record.state) {
    case JobState::Queued:
      record.state = JobState::Cancelled;
      finish("", record, nullptr);
      return Removal::Cancelled;
    case JobState::Running:  // its worker records it as cancelled
      emit({JobEvent::Kind::CancelRequested, id});
      return Removal::Cancelled;
    default:
      remove_files(id);
      std::fprintf(stderr, "job %s deleted\n", id.c_str());
      return Removal::Deleted;
  }
}

Store::Counts DirectoryStore::counts() {
  Counts c;
  std::lock_guard lock(mutex_);
  for (const auto& [id, e] : entries_) ++c.jobs_by_state[std::size_t(e.record.state)];
  return c;
}

std::optional<std::string> DirectoryStore::health() {
  std::error_code ec;
  if (!fs::is_directory(jobs_, ec)) return "the data directory is gone";
  return std::nullopt;
}

std::vector<std::string> DirectoryStore::evict() {
  std::vector<std::string> evicted = retention_.over_limits();
  for (const std::string& id : evicted) entries_.erase(id);
  return evicted;
}

void DirectoryStore::remove_files(const std::string& id) {
  fs::path doomed = jobs_ / (std::string(kRemoving) + id);
  std::error_code ignored;
  fs::rename(dir(id), doomed, ignored);
  fs::remove_all(doomed, ignored);
}

std::uintmax_t DirectoryStore::bytes_used(const std::string& id) const {
  std::uintmax_t total = 0;
  std::error_code ignored;
  for (auto it = fs::recursive_directory_iterator(dir(id), ignored);
       it != fs::recursive_directory_iterator(); it.increment(ignored))
    if (it->is_regular_file(ignored)) total += it->file_size(ignored);
  return total;
}

}  // namespace bumprad
