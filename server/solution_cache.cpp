#include "server/solution_cache.h"

namespace bumprad {

std::shared_ptr<const LoadedSolution> SolutionCache::get(const std::string& id) {
  {
    std::lock_guard lock(mutex_);
    for (auto e = entries_.begin(); e != entries_.end(); ++e)
      if (e->first == id) {
        entries_.splice(entries_.begin(), entries_, e);
        return e->second;
      }
  }
  auto bytes = store_.read(id, Artifact::Solution);
  if (!bytes) return nullptr;
  auto loaded = std::make_shared<const LoadedSolution>(
      decode_solution(*bytes, "job " + id + "'s solution", files_));
  std::lock_guard lock(mutex_);
  entries_.remove_if([&](const auto& e) { return e.first == id; });  // loaded twice at once
  entries_.emplace_front(id, loaded);
  if (entries_.size() > capacity_) entries_.pop_back();
  return loaded;
}

}  // namespace bumprad
