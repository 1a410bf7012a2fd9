// The HTTP API's JSON: job requests merge their overrides into the stored scene and name the
// request's own fields when they are wrong; job records survive a round trip to disk.
#include "protocol/api_json.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "protocol/builtin_scenes.h"

namespace bumprad {
namespace {

using json = nlohmann::json;

void expect_rejected(const json& request, const std::string& pointer, const std::string& reason) {
  try {
    parse_job_request(request.dump(), ImageFiles::refused());
    ADD_FAILURE() << "accepted; expected " << pointer << ": " << reason;
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), pointer) << e.what();
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
  }
}

TEST(ApiJson, BuiltinJobWithOverridesStoresTheSceneItSolves) {
  json request = {{"builtin", "wrinkled-box"},
                  {"bumps", {{"wrinkles", {{"type", "dimples"}, {"amplitude", 0.02}}}}},
                  {"solver", {{"max_shots", 40}}},
                  {"preview_every", 8}};
  JobRequest job = parse_job_request(request.dump(), ImageFiles::refused());
  EXPECT_EQ(job.scene_name, "builtin:wrinkled-box");
  EXPECT_EQ(job.scene.solver.max_shots, 40);
  EXPECT_EQ(job.scene.solver.preview_every, 8);
  ASSERT_EQ(job.scene.bumps.size(), 1u);
  EXPECT_EQ(job.scene.bumps[0].type, BumpType::Dimples);

  // The stored text alone gives the same scene: what a restarted server re-loads.
  Scene again = parse_scene(std::string_view(job.scene_json));
  EXPECT_EQ(again.solver.max_shots, 40);
  EXPECT_EQ(again.solver.preview_every, 8);
  EXPECT_EQ(again.solver.unshot_fraction, job.scene.solver.unshot_fraction);
  EXPECT_EQ(again.bumps[0].type, BumpType::Dimples);
  EXPECT_EQ(again.bumps[0].amplitude, 0.02);
}

// The job list names an inline scene by its description (cut at a word), not "inline".
TEST(ApiJson, AnInlineJobIsNamedByItsScenesDescription) {
  json scene = json::parse(*find_builtin_scene("cornell"));
  scene["description"] = "A short room";
  EXPECT_EQ(parse_job_request(json{{"scene", scene}}.dump(), ImageFiles::refused()).scene_name,
            "A short room");
  scene["description"] =
      "A room of several boxes, lamps and mirrors that goes on for longer than a list can show";
  EXPECT_EQ(parse_job_request(json{{"scene", scene}}.dump(), ImageFiles::refused()).scene_name,
            "A room of several boxes, lamps and mirrors that goes on for…");
  scene.erase("description");
  EXPECT_EQ(parse_job_request(json{{"scene", scene}}.dump(), ImageFiles::refused()).scene_name,
            "inline scene");
}

TEST(ApiJson, JobsWithoutPreviewEveryGetAboutTwentySteps) {
  JobRequest job = parse_job_request(R"({"builtin": "cornell", "solver": {"max_shots": 90}})",
                                     ImageFiles::refused());
  EXPECT_EQ(job.scene.solver.preview_every, 5);  // ceil(90 / 20)
  EXPECT_EQ(parse_scene(std::string_view(job.scene_json)).solver.preview_every, 5);
}

TEST(ApiJson, RejectionsNameTheRequestsField) {
  EXPECT_THROW(parse_job_request("{\"builtin\": ", ImageFiles::refused()), MalformedJson);
  expect_rejected(json::array(), "", "must be a JSON object");
  expect_rejected({{"builtin", "cornell"}, {"colour", 1}}, "/colour", "unknown key for a job");
  expect_rejected({{"builtin", "attic"}}, "/builtin", "unknown built-in scene \"attic\"");
  expect_rejected(json::object(), "/scene", "give either");
  expect_rejected({{"scene", 3}}, "/scene", "must be a scene object");
  json scene = json::parse(
      R"({"camera": {"position": [0,0,-5], "look_at": [0,0,0]}, "materials": {"m": {"reflectance": 0.5}},
      "objects": [{"type": "quad", "material": "m", "vertices": [[0,0,0],[1,0,0],[1,1,0]]}]})");
  expect_rejected({{"scene", scene}}, "/scene/objects/0/vertices", "exactly 4 entries");
  expect_rejected({{"builtin", "wrinkled-box"}, {"bumps", {{"ripples", {{"type", "noise"}}}}}},
                  "/bumps/ripples", "no bump function of this name");
  expect_rejected({{"builtin", "cornell"}, {"solver", {{"max_shots", 0}}}}, "/solver/max_shots",
                  "");
  expect_rejected({{"builtin", "cornell"}, {"preview_every", "often"}}, "/preview_every", "");
}

TEST(ApiJson, JobRecordsRoundTrip) {
  JobRecord j;
  j.id = "0123abcd";
  j.state = JobState::Interrupted;
  j.scene_name = "inline";
  j.created = 1.7e9;
  j.started = 1.7e9 + 1;
  j.shots = 40;
  j.max_shots = 100;
  j.preview_every = 10;
  j.unshot_fraction = 0.25;
  j.step = 4;
  j.first_kept_step = 2;
  j.elements = 1234;
  j.patches = 321;
  j.seconds_solve = 1.5;
  j.error = "the server stopped while the job ran";
  EXPECT_FALSE(json::parse(job_to_json(j)).contains("estimated_error")) << "none without one";
  j.estimated_error = 0.021;
  j.estimated_error_se = 0.002;
  JobRecord back = job_from_json(job_to_json(j));
  EXPECT_EQ(job_to_json(back), job_to_json(j));
  json d = json::parse(job_to_json(j));
  EXPECT_EQ(d["estimated_error"]["relative_rms"], 0.021);
  EXPECT_EQ(d["state"], "interrupted");
  EXPECT_EQ(d["latest_step_url"], "/v1/jobs/0123abcd/steps/4.png");
  EXPECT_FALSE(d["links"].contains("image")) << "only done jobs link their image";
  EXPECT_THROW(job_from_json(R"({"id": "x"})"), SceneError);
}

TEST(ApiJson, RetextureRequests) {
  Scene solved = parse_job_request(R"({"builtin": "wrinkled-box"})", ImageFiles::refused()).scene;
  RetextureRequest r = parse_retexture_request(
      R"({"bumps": {"wrinkles": {"type": "bricks"}}, "camera": {"width": 64, "height": 48},
          "format": "exr"})",
      solved, ImageFiles::refused());
  EXPECT_EQ(r.scene.bumps[0].type, BumpType::Bricks);
  EXPECT_EQ(r.scene.camera.width, 64);
  EXPECT_EQ(r.format, ImageFormat::Exr);
  EXPECT_EQ(parse_retexture_request("", solved, ImageFiles::refused()).format, ImageFormat::Png);
  try {
    parse_retexture_request(R"({"format": "tiff"})", solved, ImageFiles::refused());
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), "/format");
  }
  // Drafts for interactive editing: one ray a pixel, few glossy samples, JPEG.
  solved.camera.antialias = 3;
  solved.camera.glossy_samples = 16;
  RetextureRequest draft = parse_retexture_request(R"({"quality": "draft", "format": "jpeg"})",
                                                   solved, ImageFiles::refused());
  EXPECT_EQ(draft.scene.camera.antialias, 1);
  EXPECT_EQ(draft.scene.camera.glossy_samples, 2);
  EXPECT_EQ(draft.format, ImageFormat::Jpeg);
  EXPECT_EQ(parse_retexture_request(R"({"quality": "final"})", solved, ImageFiles::refused())
                .scene.camera.antialias,
            3);
  try {
    parse_retexture_request(R"({"quality": "rough"})", solved, ImageFiles::refused());
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), "/quality");
    EXPECT_NE(std::string(e.what()).find("expected final or draft"), std::string::npos);
  }
  try {
    parse_retexture_request(R"({"camera": {"width": -1}})", solved, ImageFiles::refused());
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), "/camera/width");
  }
}

TEST(ApiJson, ProblemDetails) {
  json p = json::parse(problem_json(422, "Invalid scene", "/x: bad", "/x"));
  EXPECT_EQ(p["status"], 422);
  EXPECT_EQ(p["title"], "Invalid scene");
  EXPECT_EQ(p["field"], "/x");
  EXPECT_FALSE(json::parse(problem_json(404, "Not found", "no route"))["field"].is_string());
  EXPECT_GE(json::parse(builtin_scenes_json())["scenes"].size(), 3u);
}

TEST(ApiJson, ProblemDetailsQuoteInvalidUtf8Escaped) {
  EXPECT_EQ(valid_utf8("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80"),
            "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80");
  EXPECT_EQ(valid_utf8("a\xff"
                       "b"),
            "a\\xFFb");
  EXPECT_EQ(valid_utf8("\xc0\xaf"), "\\xC0\\xAF");           // overlong '/'
  EXPECT_EQ(valid_utf8("\xed\xa0\x80"), "\\xED\\xA0\\x80");  // a surrogate
  EXPECT_EQ(valid_utf8("\xe2\x82"), "\\xE2\\x82");           // cut short
  json p = json::parse(problem_json(404, "Not found", "no such resource: /v1/\xff", "/\xfe"));
  EXPECT_EQ(p["detail"], "no such resource: /v1/\\xFF");
  EXPECT_EQ(p["field"], "/\\xFE");
}

// Found by the fuzz target: a number beyond int was converted with undefined behaviour.
TEST(ApiJson, RecordsAndEventsRefuseNumbersOutOfRange) {
  try {
    step_event_from_json(
        R"({"step": 3, "shots": 30, "max_shots": 111111111111111111100, "unshot_fraction": 0.2,
            "preview": "/v1/jobs/0123456789abcdef/steps/3.png"})");
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.pointer(), "/max_shots");
  }
  JobRecord r;
  r.id = "0123456789abcdef";
  json record = json::parse(job_to_json(r));
  EXPECT_EQ(job_from_json(record.dump()).id, r.id);
  record["step"] = -1;
  EXPECT_THROW(job_from_json(record.dump()), SceneError);
  record["step"] = 1e300;
  EXPECT_THROW(job_from_json(record.dump()), SceneError);
}

}  // namespace
}  // namespace bumprad
