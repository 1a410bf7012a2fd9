#include "server/retention.h"

#include <algorithm>
#include <utility>

namespace bumprad {

void Retention::keep(const std::string& id, double last_used, std::uintmax_t bytes) {
  forget(id);
  kept_[id] = {last_used, bytes};
  total_ += bytes;
}

void Retention::touch(const std::string& id, double now) {
  auto it = kept_.find(id);
  if (it != kept_.end()) it->second.last_used = now;
}

void Retention::forget(const std::string& id) {
  auto it = kept_.find(id);
  if (it == kept_.end()) return;
  total_ -= it->second.bytes;
  kept_.erase(it);
}

std::vector<std::string> Retention::over_limits() {
  std::vector<std::string> evicted;
  if (kept_.size() <= limits_.max_jobs && total_ <= limits_.max_bytes) return evicted;
  std::vector<std::pair<double, std::string>> by_use;
  for (const auto& [id, k] : kept_) by_use.emplace_back(k.last_used, id);
  std::sort(by_use.begin(), by_use.end());
  for (const auto& [used, id] : by_use) {
    if (kept_.size() <= limits_.max_jobs && total_ <= limits_.max_bytes) break;
    evicted.push_back(id);
    forget(id);
  }
  return evicted;
}

}  // namespace bumprad
