// Solved jobs for re-texturing: loaded from the store once, then served from memory, the
// least recently used going first past the capacity; a job without a solution is null.
#include "server/solution_cache.h"

#include <gtest/gtest.h>

#include "server/directory_store.h"
#include "server/job_runner.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

// A data directory with `count` done jobs; their ids.
std::vector<std::string> done_jobs(DirectoryStore& store, int count) {
  Metrics metrics;
  Watchdog watchdog;
  JobRunner runner(store, metrics, watchdog, {});
  std::vector<std::string> ids;
  for (int i = 0; i < count; ++i) {
    JobRecord record;
    record.id = new_job_id();
    record.scene_name = "inline";
    store.submit(record, test::small_scene_json(10), "");
    std::atomic<StopReason> reason{StopReason::None};
    runner.run("worker", *store.claim("worker"), {}, reason);
    ids.push_back(record.id);
  }
  return ids;
}

TEST(SolutionCache, LoadsOnceKeepsTheNewestAndForgetsTheOldest) {
  DirectoryStore store(test::fresh_temp_dir("solution-cache"), {});
  const std::vector<std::string> ids = done_jobs(store, 2);
  SolutionCache cache(store, 1, ImageFiles::refused());
  const auto first = cache.get(ids[0]);
  ASSERT_TRUE(first);
  EXPECT_FALSE(first->solution.mesh->elements.empty());
  EXPECT_TRUE(first->solution.map);     // the small scene is bumpy
  EXPECT_EQ(cache.get(ids[0]), first);  // from memory
  const auto second = cache.get(ids[1]);
  ASSERT_TRUE(second);
  EXPECT_NE(second, first);
  const auto again = cache.get(ids[0]);  // evicted by the second: loaded anew
  ASSERT_TRUE(again);
  EXPECT_NE(again, first);
  EXPECT_EQ(again->solution.radiosity, first->solution.radiosity);
  EXPECT_EQ(cache.get("0123456789abcdef"), nullptr);
}

}  // namespace
}  // namespace bumprad
