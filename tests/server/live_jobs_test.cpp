// The jobs viewers watch, kept current from the store's events: one shared view per job,
// none for a job the store does not have, and a view that follows claims and steps.
#include "server/live_jobs.h"

#include <gtest/gtest.h>

#include "server/directory_store.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

TEST(LiveJobs, OneSharedViewPerJobThatFollowsTheStore) {
  DirectoryStore store(test::fresh_temp_dir("live-jobs"), {});
  LiveJobs live(store);
  EXPECT_EQ(live.watch("0123456789abcdef"), nullptr);

  JobRecord record;
  record.id = new_job_id();
  record.scene_name = "inline";
  store.submit(record, test::small_scene_json(10), "");
  const std::shared_ptr<Job> job = live.watch(record.id);
  ASSERT_TRUE(job);
  EXPECT_EQ(live.watch(record.id), job);
  EXPECT_EQ(job->record().state, JobState::Queued);

  int woken = 0;
  job->watch([&] { ++woken; });
  Claim claim = *store.claim("worker");
  EXPECT_EQ(job->record().state, JobState::Running);  // this store's events come at once
  store.progress("worker", claim.record, "not really a PNG");
  const Job::View view = job->view();
  EXPECT_EQ(view.record.step, 1);
  ASSERT_TRUE(view.preview);
  EXPECT_EQ(*view.preview, "not really a PNG");
  EXPECT_GE(woken, 2);
}

}  // namespace
}  // namespace bumprad
