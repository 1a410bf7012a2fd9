// Jobs through the store and the scheduler's workers in process: they run to done, cancels
// and time limits end them as they say, a shutdown releases running jobs, and a restart
// finds what the data directory holds.
#include "server/scheduler.h"

#include <gtest/gtest.h>

#include "tests/server/in_process.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

std::string job(int max_shots, bool endless = false) {
  return test::small_job_json(max_shots, 5, endless);
}

TEST(Scheduler, AJobRunsToDoneWithItsStepsAndFiles) {
  test::InProcessServer s(test::fresh_temp_dir("scheduler"));
  const std::string id = s.submit(job(10));
  JobRecord done = s.wait_for(id, JobState::Done);
  EXPECT_EQ(done.shots, 10);
  EXPECT_GE(done.step, 2);  // a draft, then the final image
  EXPECT_TRUE(std::filesystem::exists(s.store.path(id, Artifact::Solution)));
  EXPECT_TRUE(std::filesystem::exists(s.store.step_path(id, done.step)));
  ASSERT_NE(s.node.solutions.get(id), nullptr);
  EXPECT_EQ(s.store.cancel_or_delete(id), Store::Removal::Deleted);
  EXPECT_EQ(s.store.find(id), std::nullopt);
  EXPECT_FALSE(std::filesystem::exists(s.store.dir(id)));
}

TEST(Scheduler, CancelsEndQueuedAndRunningJobs) {
  test::InProcessServer s(test::fresh_temp_dir("scheduler"));
  const std::string running = s.submit(job(0, true));
  const std::string queued = s.submit(job(10));
  s.wait_for(running, JobState::Running);
  EXPECT_EQ(s.store.cancel_or_delete(queued), Store::Removal::Cancelled);
  EXPECT_EQ(s.store.find(queued)->state, JobState::Cancelled);
  EXPECT_EQ(s.store.cancel_or_delete(running), Store::Removal::Cancelled);
  EXPECT_EQ(s.wait_for(running, JobState::Cancelled, 5).error, "");
}

TEST(Scheduler, AJobPastItsTimeLimitFails) {
  NodeOptions options = test::node_options(test::fresh_temp_dir("scheduler"));
  options.runner.job_timeout_s = 0.5;
  test::InProcessServer s(options);
  const std::string id = s.submit(job(0, true));
  JobRecord failed = s.wait_for(id, JobState::Failed, 10);
  EXPECT_NE(failed.error.find("time limit of 0.5 s"), std::string::npos) << failed.error;
}

TEST(Scheduler, AShutdownReleasesTheRunningJob) {
  test::InProcessServer s(test::fresh_temp_dir("scheduler"));
  const std::string id = s.submit(job(0, true));
  s.wait_for(id, JobState::Running);
  s.node.shutdown();
  JobRecord r = *s.store.find(id);
  EXPECT_EQ(r.state, JobState::Interrupted);
  EXPECT_NE(r.error.find("shut down"), std::string::npos) << r.error;
}

TEST(Scheduler, ARestartFindsDoneJobsAndInterruptsRunningOnes) {
  auto dir = test::fresh_temp_dir("scheduler");
  std::string done, running;
  {
    test::InProcessServer s(dir);
    done = s.submit(job(5));
    s.wait_for(done, JobState::Done);
    running = s.submit(job(0, true));
    s.wait_for(running, JobState::Running);
  }
  // A crash: the record on disk still says running. (The node's own shutdown records it
  // as interrupted; here the record is put back as a kill -9 leaves it.)
  const auto record_file = dir / "jobs" / running / "job.json";
  JobRecord r = job_from_json(test::read_file(record_file));
  r.state = JobState::Running;
  test::write_file(record_file, job_to_json(r));
  test::InProcessServer s(dir);
  EXPECT_EQ(s.store.find(done)->state, JobState::Done);
  JobRecord interrupted = *s.store.find(running);
  EXPECT_EQ(interrupted.state, JobState::Interrupted);
  EXPECT_NE(interrupted.error.find("submit it again"), std::string::npos);
}

}  // namespace
}  // namespace bumprad
