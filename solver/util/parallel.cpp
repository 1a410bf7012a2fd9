#include "solver/util/parallel.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace bumprad {

void parallel_for(int count, const std::function<void(int)>& work, std::stop_token stop) {
  std::atomic<int> next{0};
  auto run = [&] {
    for (int i; !stop.stop_requested() && (i = next++) < count;) work(i);
  };
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::jthread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(run);
  run();
}

}  // namespace bumprad
