// Solved jobs held in memory for re-texturing: the scene and perturbed map of the most
// recently used done jobs, loaded from the store on a miss, and with each the views of it
// that re-textures rendered (SolutionView: what no bump function changes, per camera), so
// that the next re-texture through the same camera costs the shading alone.
#pragma once

#include <list>
#include <memory>
#include <mutex>
#include <string>

#include "protocol/solution_file.h"
#include "server/store.h"
#include "solver/solution.h"

namespace bumprad {

class SolutionCache {
 public:
  SolutionCache(Store& store, std::size_t capacity, ImageFiles files)
      : store_(store), capacity_(capacity), files_(std::move(files)) {}

  // A done job's solved scene and map; null when the store has no solution for it. Throws
  // SolutionFileError when the stored one is damaged. Loading happens outside the lock.
  std::shared_ptr<const LoadedSolution> get(const std::string& id);

  // The view of job `id`'s solution `solved` (from get()) through `camera`: the one kept for
  // the same view (same_view()), or a new one, kept (the most recent kViewsPerJob a job).
  std::shared_ptr<const SolutionView> view(const std::string& id,
                                           const std::shared_ptr<const LoadedSolution>& solved,
                                           const Camera& camera);
  static constexpr std::size_t kViewsPerJob = 4;  // a final and a draft camera, and moves

 private:
  struct Entry {
    std::string id;
    std::shared_ptr<const LoadedSolution> solved;
    std::list<std::shared_ptr<const SolutionView>> views;  // most recent first
  };
  Store& store_;
  const std::size_t capacity_;
  const ImageFiles files_;
  std::mutex mutex_;
  std::list<Entry> entries_;
};

}  // namespace bumprad
