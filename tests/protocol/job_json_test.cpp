// Job records, step events and problem details through their JSON: what goes out comes
// back, and bytes that are not UTF-8 are escaped rather than sent broken.
#include "protocol/job_json.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace bumprad {
namespace {

using json = nlohmann::json;

TEST(JobJson, ARecordComesBackAsItWent) {
  JobRecord r;
  r.id = "0123456789abcdef";
  r.state = JobState::Done;
  r.scene_name = "builtin:cornell";
  r.created = 1.5e9;
  r.started = 1.5e9 + 1;
  r.finished = 1.5e9 + 3.25;
  r.shots = 640;
  r.max_shots = 2000;
  r.preview_every = 25;
  r.unshot_fraction = 0.005;
  r.step = 26;
  r.first_kept_step = 3;
  r.elements = 2305;
  r.patches = 632;
  r.seconds_solve = 1.6;
  r.seconds_texture = 0.02;
  r.seconds_previews = 0.4;
  r.estimated_error = 0.018;
  r.estimated_error_se = 0.004;
  r.antialias = 4;
  r.warnings = {"/scene/objects/0: \"room.glb\": 3 degenerate triangles dropped"};
  r.history = {{0, 0.01, 1}, {25, 0.4, 0.3}, {640, 1.6, 0.005}};
  const JobRecord back = job_from_json(job_to_json(r));
  EXPECT_EQ(back.warnings, r.warnings);
  EXPECT_EQ(back.history, r.history);
  // The list leaves histories out: one a job would make it grow with every step.
  EXPECT_TRUE(jobs_from_json(jobs_to_json({r}))[0].history.empty());
  EXPECT_EQ(job_to_json(back), job_to_json(r));
  EXPECT_EQ(back.state, JobState::Done);
  EXPECT_EQ(back.first_kept_step, 3);
  EXPECT_EQ(back.estimated_error_se, 0.004);
  EXPECT_EQ(back.antialias, 4);
  const json j = json::parse(job_to_json(r));
  EXPECT_EQ(j["links"]["image"], "/v1/jobs/0123456789abcdef/image");
}

// A history keeps its first and newest points and thins the rest, so a long solve's curve
// stays whole in a bounded record.
TEST(JobJson, AHistoryIsThinnedNotCut) {
  JobRecord r;
  for (int shot = 0; shot < 10'000; ++shot) add_progress(r, {shot, 0.01 * shot, 1.0 / (1 + shot)});
  ASSERT_LE(r.history.size(), JobRecord::kMaxHistory);
  EXPECT_GT(r.history.size(), JobRecord::kMaxHistory / 2);
  EXPECT_EQ(r.history.front().shots, 0);
  EXPECT_EQ(r.history.back().shots, 9'999);
  for (std::size_t i = 1; i < r.history.size(); ++i)
    ASSERT_LT(r.history[i - 1].shots, r.history[i].shots);
  EXPECT_EQ(job_from_json(job_to_json(r)).history, r.history);
}

TEST(JobJson, EveryStateHasAName) {
  for (JobState s : {JobState::Queued, JobState::Running, JobState::Done, JobState::Failed,
                     JobState::Cancelled, JobState::Interrupted})
    EXPECT_EQ(job_state_from(to_string(s)), s);
  EXPECT_EQ(job_state_from("sleeping"), std::nullopt);
  EXPECT_FALSE(is_finished(JobState::Running));
  EXPECT_TRUE(is_finished(JobState::Interrupted));
}

TEST(JobJson, StepEventsAndRequests) {
  JobRecord r;
  r.id = "00000000000000ff";
  r.step = 4;
  r.shots = 100;
  r.max_shots = 400;
  r.unshot_fraction = 0.25;
  const StepEvent e = step_event_from_json(step_event_json(r));
  EXPECT_EQ(e.step, 4);
  EXPECT_EQ(e.shots, 100);
  EXPECT_EQ(e.preview, step_url(r.id, 4));
  const json request =
      json::parse(job_request_json({"cornell", "", R"({"b": {"type": "flat"}})", 50, {}}));
  EXPECT_EQ(request["builtin"], "cornell");
  EXPECT_EQ(request["bumps"]["b"]["type"], "flat");
  EXPECT_EQ(request["solver"]["max_shots"], 50);
  EXPECT_THROW(job_request_json({"", "{not json", "", {}, {}}), MalformedJson);
}

TEST(JobJson, ProblemsAreValidJsonWhateverTheyQuote) {
  const json p =
      json::parse(problem_json(422, "Invalid request", "bad \xff\xfe byte", "/objects/0"));
  EXPECT_EQ(p["status"], 422);
  EXPECT_EQ(p["detail"], "bad \\xFF\\xFE byte");
  EXPECT_EQ(p["field"], "/objects/0");
  EXPECT_EQ(valid_utf8("caf\xc3\xa9"), "caf\xc3\xa9");  // well-formed: kept
  EXPECT_FALSE(json::parse(problem_json(404, "Not found", "x")).contains("field"));
}

}  // namespace
}  // namespace bumprad
