#include "server/job_store.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <system_error>

#include "solver/atomic_file.h"

namespace bumprad {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kRecord = "job.json";
constexpr std::string_view kRemoving = ".removing-";

// Temporary files of atomic writes (solver/atomic_file.cpp) are ".NAME.tmp-PID-N.EXT".
bool is_temporary(const std::string& name) {
  return name.starts_with('.') && name.find(".tmp-") != std::string::npos;
}

// Removes the temporary files a crash left in a job's folder, and brings the record's step
// range up to the step previews on disk.
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

}  // namespace

JobStore::JobStore(fs::path data_dir) : jobs_(data_dir / "jobs") {
  fs::create_directories(jobs_);
  fs::path lock = data_dir / "lock";
  lock_fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0 || ::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    if (lock_fd_ >= 0) ::close(lock_fd_);
    throw std::runtime_error(data_dir.string() +
                             " is in use by another bumprad serve (or cannot be locked)");
  }
}

JobStore::~JobStore() {
  ::close(lock_fd_);
}

std::string JobStore::new_id() {
  static thread_local std::mt19937_64 random{std::random_device{}()};
  const char* hex = "0123456789abcdef";
  std::uint64_t bits = random();
  std::string id(16, '0');
  for (char& c : id) {
    c = hex[bits & 15];
    bits >>= 4;
  }
  return id;
}

bool JobStore::is_valid_id(std::string_view id) {
  return id.size() == 16 && id.find_first_not_of("0123456789abcdef") == std::string_view::npos;
}

fs::path JobStore::scene_path(const std::string& id) const {
  return dir(id) / "scene.json";
}

fs::path JobStore::solution_path(const std::string& id) const {
  return dir(id) / "solution.bumprad";
}

fs::path JobStore::image_path(const std::string& id, ImageFormat format) const {
  return dir(id) / (format == ImageFormat::Png ? "image.png" : "image.exr");
}

fs::path JobStore::step_path(const std::string& id, int step) const {
  return dir(id) / "steps" / (std::to_string(step) + ".png");
}

void JobStore::writing(const std::string& what, const std::function<void()>& write) const {
  try {
    write();
  } catch (const std::system_error& e) {
    if (e.code() == std::errc::no_space_on_device || e.code().value() == EDQUOT)
      throw StoreFull("the server's disk is full (writing " + what + "); try again later");
    throw std::runtime_error("cannot write " + what + ": " + e.code().message());
  }
}

void JobStore::create(const JobRecord& job, std::string_view scene_json) {
  try {
    writing("the job's folder", [&] { fs::create_directories(dir(job.id) / "steps"); });
    writing("the job's scene", [&] { write_file_atomically(scene_path(job.id), scene_json); });
    save_record(job);
  } catch (...) {
    remove(job.id);
    throw;
  }
}

void JobStore::save_record(const JobRecord& job) {
  writing("the job's record",
          [&] { write_file_atomically(dir(job.id) / kRecord, job_to_json(job)); });
}

void JobStore::save_step(const std::string& id, int step, std::string_view png) {
  writing("step " + std::to_string(step), [&] { write_file_atomically(step_path(id, step), png); });
}

void JobStore::drop_step(const std::string& id, int step) {
  std::error_code ignored;
  fs::remove(step_path(id, step), ignored);
}

void JobStore::save_file(const fs::path& path, std::string_view bytes) {
  writing("the job's " + path.filename().string(), [&] { write_file_atomically(path, bytes); });
}

std::optional<std::string> JobStore::read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

std::vector<JobStore::Stored> JobStore::load_all() {
  std::vector<Stored> out;
  for (const auto& entry : fs::directory_iterator(jobs_)) {
    std::string name = entry.path().filename().string();
    std::error_code ignored;
    if (name.starts_with(kRemoving)) {
      fs::remove_all(entry.path(), ignored);
      continue;
    }
    if (!is_valid_id(name)) continue;  // not ours: leave it alone
    auto record = read(entry.path() / kRecord);
    auto scene = read(scene_path(name));
    try {
      if (record && scene) {
        Stored stored{job_from_json(*record), *scene};
        scan_files(entry.path(), stored.record);
        out.push_back(std::move(stored));
        continue;
      }
    } catch (const std::exception&) {
    }
    remove(name);
  }
  return out;
}

void JobStore::remove(const std::string& id) {
  fs::path doomed = jobs_ / (std::string(kRemoving) + id);
  std::error_code ignored;
  fs::rename(dir(id), doomed, ignored);
  fs::remove_all(doomed, ignored);
}

std::uintmax_t JobStore::bytes_used(const std::string& id) const {
  std::uintmax_t total = 0;
  std::error_code ignored;
  for (auto it = fs::recursive_directory_iterator(dir(id), ignored);
       it != fs::recursive_directory_iterator(); it.increment(ignored))
    if (it->is_regular_file(ignored)) total += it->file_size(ignored);
  return total;
}

}  // namespace bumprad
