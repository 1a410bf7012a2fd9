// Solved jobs held in memory for re-texturing: the scene and perturbed map of the most
// recently used done jobs, loaded from the store on a miss.
#pragma once

#include <list>
#include <memory>
#include <mutex>
#include <string>

#include "protocol/solution_file.h"
#include "server/store.h"

namespace bumprad {

class SolutionCache {
 public:
  SolutionCache(Store& store, std::size_t capacity, ImageFiles files)
      : store_(store), capacity_(capacity), files_(std::move(files)) {}

  // A done job's solved scene and map; null when the store has no solution for it. Throws
  // SolutionFileError when the stored one is damaged. Loading happens outside the lock.
  std::shared_ptr<const LoadedSolution> get(const std::string& id);

 private:
  Store& store_;
  const std::size_t capacity_;
  const ImageFiles files_;
  std::mutex mutex_;
  std::list<std::pair<std::string, std::shared_ptr<const LoadedSolution>>> entries_;
};

}  // namespace bumprad
