// The data-directory store in process: idempotent submissions, the queue limit, retention
// of finished jobs, and removal that leaves nothing behind.
#include "server/directory_store.h"

#include <chrono>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/server/in_process.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

using test::request;
using verb = http::verb;

Request keyed_submit(const std::string& body, const std::string& key) {
  Request r = request(verb::post, "/v1/jobs", body);
  r.set("Idempotency-Key", key);
  return r;
}

TEST(DirectoryStore, ARetriedSubmissionWithItsKeyGetsTheSameJob) {
  auto dir = test::fresh_temp_dir("store");
  std::string id;
  {
    test::InProcessServer s(dir);
    Response first = s.answer(keyed_submit(test::small_job_json(5, 5), "order-17"));
    ASSERT_EQ(first.result_int(), 202) << first.body();
    id = job_from_json(first.body()).id;
    Response again = s.answer(keyed_submit(test::small_job_json(5, 5), "order-17"));
    ASSERT_EQ(again.result_int(), 202) << again.body();
    EXPECT_EQ(job_from_json(again.body()).id, id);
    EXPECT_EQ(again["Idempotent-Replayed"], "true");
    EXPECT_EQ(s.store.list().size(), 1u);

    Response other = s.answer(keyed_submit(test::small_job_json(6, 5), "order-17"));
    EXPECT_EQ(other.result_int(), 422);
    EXPECT_EQ(nlohmann::json::parse(other.body())["field"], "Idempotency-Key");
    Response bad = s.answer(keyed_submit(test::small_job_json(5, 5), "tab\there"));
    EXPECT_EQ(bad.result_int(), 400);
    EXPECT_EQ(nlohmann::json::parse(bad.body())["field"], "Idempotency-Key");
    s.wait_for(id, JobState::Done);
  }
  test::InProcessServer s(dir);  // the key outlives a restart
  Response after = s.answer(keyed_submit(test::small_job_json(5, 5), "order-17"));
  EXPECT_EQ(job_from_json(after.body()).id, id);
}

TEST(DirectoryStore, SubmitRefusesPastTheQueueLimit) {
  NodeOptions options = test::node_options(test::fresh_temp_dir("store"));
  options.store.max_queue = 1;
  test::InProcessServer s(options);
  const std::string running = s.submit(test::small_job_json(0, 5, true));
  s.wait_for(running, JobState::Running);
  s.submit(test::small_job_json(5, 5));
  Response full = s.answer(request(verb::post, "/v1/jobs", test::small_job_json(5, 5)));
  EXPECT_EQ(full.result_int(), 429);
  s.store.cancel_or_delete(running);
}

TEST(DirectoryStore, RetentionEvictsTheLeastRecentlyUsedFinishedJobs) {
  NodeOptions options = test::node_options(test::fresh_temp_dir("store"));
  options.store.retention.max_jobs = 2;
  test::InProcessServer s(options);
  std::vector<std::string> ids;
  for (int i = 0; i < 2; ++i) {
    ids.push_back(s.submit(test::small_job_json(3, 3)));
    s.wait_for(ids.back(), JobState::Done);
  }
  s.store.touch(ids[0]);  // now the second is the least recently used
  ids.push_back(s.submit(test::small_job_json(3, 3)));
  s.wait_for(ids.back(), JobState::Done);
  EXPECT_TRUE(s.store.find(ids[0]));
  EXPECT_FALSE(s.store.find(ids[1]));
  // The evicted job's files go after its entry, outside the store's lock, so the third job
  // can show as done a moment before they are gone (this failed once under a loaded ctest).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::filesystem::exists(s.store.dir(ids[1])) &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_FALSE(std::filesystem::exists(s.store.dir(ids[1])));
  EXPECT_TRUE(s.store.find(ids[2]));
}

TEST(DirectoryStore, ASecondStoreOnTheSameDirectoryIsRefused) {
  auto dir = test::fresh_temp_dir("store");
  DirectoryStore first(dir, {});
  EXPECT_THROW(DirectoryStore(dir, {}), std::runtime_error);
}

}  // namespace
}  // namespace bumprad
