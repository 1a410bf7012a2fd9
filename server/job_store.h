// The data directory: one folder per job holding its record, scene, solution with the
// perturbed map, final images and kept step previews. Every file is written atomically and
// a job's record is written last, so a crash never leaves half a job that looks whole.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "protocol/api_json.h"

namespace bumprad {

// The data directory's disk is full. Like every error from the store, its message names
// the job's file, never the server's path.
class StoreFull : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class JobStore {
 public:
  // Creates <data_dir>/jobs if needed and locks the directory for this process: a second
  // server on the same directory is refused (std::runtime_error) rather than sharing it.
  explicit JobStore(std::filesystem::path data_dir);
  ~JobStore();
  JobStore(const JobStore&) = delete;
  JobStore& operator=(const JobStore&) = delete;

  // A fresh random id (16 hex digits); is_valid_id() refuses anything else, so no id from
  // a URL can name a path outside the store.
  static std::string new_id();
  static bool is_valid_id(std::string_view id);

  std::filesystem::path dir(const std::string& id) const { return jobs_ / id; }
  std::filesystem::path scene_path(const std::string& id) const;
  std::filesystem::path solution_path(const std::string& id) const;
  std::filesystem::path image_path(const std::string& id, ImageFormat format) const;
  std::filesystem::path step_path(const std::string& id, int step) const;

  // A new job's folder with its scene, then its record; if either cannot be written, no
  // folder is left behind. Writes throw StoreFull or std::runtime_error.
  void create(const JobRecord& job, std::string_view scene_json);
  void save_record(const JobRecord& job);
  void save_step(const std::string& id, int step, std::string_view png);
  void drop_step(const std::string& id, int step);
  void save_file(const std::filesystem::path& path, std::string_view bytes);

  // The whole file, or nullopt when it is not there.
  static std::optional<std::string> read(const std::filesystem::path& path);

  struct Stored {
    JobRecord record;
    std::string scene_json;
  };
  // Every job with a readable record and scene. Folders without them (a submit cut short)
  // are removed, and so are leftovers of removals cut short and temporary files of writes
  // cut short. A record's step range is read from the steps on disk, which the record
  // may not have caught up with (it is rewritten only when the job starts and ends).
  std::vector<Stored> load_all();

  // Removes a job's folder: renamed away first, so it vanishes whole.
  void remove(const std::string& id);
  std::uintmax_t bytes_used(const std::string& id) const;

 private:
  // Runs a write; file system errors become StoreFull or runtime_error naming `what`.
  void writing(const std::string& what, const std::function<void()>& write) const;
  std::filesystem::path jobs_;
  int lock_fd_ = -1;
};

}  // namespace bumprad
