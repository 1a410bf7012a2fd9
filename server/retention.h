// Which finished jobs a store keeps: once there are more than max_jobs, or their bytes pass
// max_bytes, the least recently used go first. Bookkeeping only; the store removes files.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace bumprad {

struct RetentionLimits {
  std::size_t max_jobs = 500;                          // finished jobs kept
  std::uintmax_t max_bytes = std::uintmax_t(4) << 30;  // their stored bytes, in all
};

class Retention {
 public:
  explicit Retention(RetentionLimits limits) : limits_(limits) {}

  void keep(const std::string& id, double last_used, std::uintmax_t bytes);
  void touch(const std::string& id, double now);  // ignored for a job it does not keep
  void forget(const std::string& id);
  // The jobs to evict so that the limits hold, least recently used first; forgotten here.
  std::vector<std::string> over_limits();

 private:
  struct Kept {
    double last_used;
    std::uintmax_t bytes;
  };
  RetentionLimits limits_;
  std::map<std::string, Kept> kept_;
  std::uintmax_t total_ = 0;
};

}  // namespace bumprad
