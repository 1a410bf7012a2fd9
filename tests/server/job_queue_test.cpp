// The job queue in process: jobs run to done, cancels and time limits end them as they
// say, and a restart finds what the data directory holds.
#include "server/job_queue.h"

#include <gtest/gtest.h>

#include "tests/server/in_process.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

JobRequest job(int max_shots, bool endless = false) {
  return parse_job_request(test::small_job_json(max_shots, 5, endless), ImageFiles::refused());
}

TEST(JobQueue, AJobRunsToDoneWithItsStepsAndFiles) {
  test::InProcessServer s(test::fresh_temp_dir("queue"));
  auto submitted = s.queue.submit(job(10));
  const std::string id = submitted->record().id;
  JobRecord done = s.wait_for(id, JobState::Done);
  EXPECT_EQ(done.shots, 10);
  EXPECT_GE(done.step, 2);  // a draft, then the final image
  EXPECT_TRUE(std::filesystem::exists(s.store.solution_path(id)));
  EXPECT_TRUE(std::filesystem::exists(s.store.step_path(id, done.step)));
  ASSERT_NE(s.queue.solution(id), nullptr);
  EXPECT_EQ(s.queue.cancel_or_delete(id), JobQueue::Removal::Deleted);
  EXPECT_EQ(s.queue.find(id), nullptr);
  EXPECT_FALSE(std::filesystem::exists(s.store.dir(id)));
}

TEST(JobQueue, CancelsEndQueuedAndRunningJobs) {
  test::InProcessServer s(test::fresh_temp_dir("queue"));
  const std::string running = s.queue.submit(job(0, true))->record().id;
  const std::string queued = s.queue.submit(job(10))->record().id;
  s.wait_for(running, JobState::Running);
  EXPECT_EQ(s.queue.cancel_or_delete(queued), JobQueue::Removal::Cancelled);
  EXPECT_EQ(s.queue.find(queued)->record().state, JobState::Cancelled);
  EXPECT_EQ(s.queue.cancel_or_delete(running), JobQueue::Removal::Cancelled);
  EXPECT_EQ(s.wait_for(running, JobState::Cancelled, 5).error, "");
}

TEST(JobQueue, AJobPastItsTimeLimitFails) {
  QueueOptions options;
  options.job_timeout_s = 0.5;
  test::InProcessServer s(test::fresh_temp_dir("queue"), options);
  const std::string id = s.queue.submit(job(0, true))->record().id;
  JobRecord failed = s.wait_for(id, JobState::Failed, 10);
  EXPECT_NE(failed.error.find("time limit of 0.5 s"), std::string::npos) << failed.error;
}

TEST(JobQueue, ARestartFindsDoneJobsAndInterruptsRunningOnes) {
  auto dir = test::fresh_temp_dir("queue");
  std::string done, running;
  {
    test::InProcessServer s(dir);
    done = s.queue.submit(job(5))->record().id;
    s.wait_for(done, JobState::Done);
    running = s.queue.submit(job(0, true))->record().id;
    s.wait_for(running, JobState::Running);
    // A crash: the record on disk still says running. (The queue's own shutdown would
    // record it as interrupted; here the record is put back as a kill -9 leaves it.)
  }
  JobRecord r = job_from_json(*JobStore::read(dir / "jobs" / running / "job.json"));
  r.state = JobState::Running;
  {
    JobStore store(dir);
    store.save_record(r);
  }
  test::InProcessServer s(dir);
  EXPECT_EQ(s.queue.find(done)->record().state, JobState::Done);
  JobRecord interrupted = s.queue.find(running)->record();
  EXPECT_EQ(interrupted.state, JobState::Interrupted);
  EXPECT_NE(interrupted.error.find("submit it again"), std::string::npos);
}

}  // namespace
}  // namespace bumprad
