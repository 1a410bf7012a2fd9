// The API's routes in process, without sockets: what each request is answered, which work
// is deferred off the network threads, and what a stopped re-texture says.
#include "server/api.h"

#include <algorithm>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "server/web_assets.h"
#include "solver/scene/scene.h"
#include "tests/server/in_process.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

using json = nlohmann::json;
using http::verb;
using test::request;

std::string detail(const Response& r) {
  return json::parse(r.body())["detail"];
}

TEST(Api, SubmitsAreParsedOffTheNetworkThreadAndRun) {
  test::InProcessServer s(test::fresh_temp_dir("api"));
  Request submit = request(verb::post, "/v1/jobs", test::small_job_json(5, 5));
  Routed routed = s.api.handle(submit);
  ASSERT_TRUE(std::holds_alternative<DeferredRequest>(routed.action));
  EXPECT_EQ(std::get<DeferredRequest>(routed.action).pool, DeferredRequest::Pool::Parse);
  Response accepted = s.answer(submit);
  ASSERT_EQ(accepted.result_int(), 202) << accepted.body();
  std::string id = json::parse(accepted.body())["id"];
  EXPECT_EQ(accepted[http::field::location], "/v1/jobs/" + id);
  s.wait_for(id, JobState::Done);

  Response head = s.answer(request(verb::head, "/v1/jobs/" + id + "/image"));
  Response get = s.answer(request(verb::get, "/v1/jobs/" + id + "/image"));
  EXPECT_EQ(head.result_int(), 200);
  EXPECT_TRUE(head.body().empty());
  EXPECT_EQ(head[http::field::content_length], std::to_string(get.body().size()));
  EXPECT_EQ(head[http::field::content_type], "image/png");

  Routed stream = s.api.handle(request(verb::head, "/v1/jobs/" + id + "/events"));
  ASSERT_TRUE(std::holds_alternative<Response>(stream.action));
  EXPECT_EQ(std::get<Response>(stream.action)[http::field::content_type], "text/event-stream");
}

// The route table is the API that protocol/openapi.json describes: the same paths, each
// with the same methods; the table has more only for the viewer's own files (GET).
TEST(Api, TheRouteTableIsTheOpenApiDescription) {
  std::string_view text;
  for (const WebAsset& asset : web_assets())
    if (asset.path == "/v1/openapi") text = asset.body;
  const json paths = json::parse(text)["paths"];
  std::set<std::string> described;
  for (const auto& [path, operations] : paths.items()) {
    described.insert(path);
    std::set<std::string> methods;
    for (const auto& [name, operation] : operations.items())
      if (name != "parameters") methods.insert(name);
    std::set<std::string> routed;
    for (const RouteSpec& r : Api::routes())
      if (r.pattern == path)
        for (verb v : r.methods) {
          std::string name(http::to_string(v));
          std::transform(name.begin(), name.end(), name.begin(), ::tolower);
          routed.insert(name);
        }
    EXPECT_EQ(routed, methods) << path;
  }
  for (const RouteSpec& r : Api::routes()) {
    if (described.contains(std::string(r.pattern))) continue;
    bool asset = false;
    for (const WebAsset& a : web_assets()) asset = asset || a.path == r.pattern;
    EXPECT_TRUE(asset) << r.pattern << " is routed but not in openapi.json";
    EXPECT_EQ(r.methods, std::vector<verb>{verb::get}) << r.pattern;
  }
}

// Every route answers a method it does not take with 405 and an Allow header from the table.
TEST(Api, MethodsARouteDoesNotTakeGet405WithTheTablesAllow) {
  test::InProcessServer s(test::fresh_temp_dir("api-405"));
  struct Case {
    verb method;
    const char* target;
    const char* allow;
  };
  for (const Case& c :
       {Case{verb::put, "/v1/jobs", "GET, HEAD, POST"},
        Case{verb::post, "/v1/jobs/abc", "GET, HEAD, DELETE"},
        Case{verb::get, "/v1/jobs/abc/retexture", "POST"},
        Case{verb::delete_, "/v1/jobs/abc/steps/3.png", "GET, HEAD"},
        Case{verb::post, "/healthz", "GET, HEAD"}, Case{verb::get, "/v1/validate", "POST"},
        Case{verb::post, "/", "GET, HEAD"}}) {
    const Response r = s.answer(request(c.method, c.target, ""));
    EXPECT_EQ(r.result_int(), 405) << c.target;
    EXPECT_EQ(r[http::field::allow], c.allow) << c.target;
  }
  EXPECT_EQ(s.answer(request(verb::get, "/v1/jobs/abc/bogus", "")).result_int(), 404);
  EXPECT_EQ(s.answer(request(verb::get, "/v1/jobs/abc/steps/x.png", "")).result_int(), 404);
  EXPECT_EQ(s.answer(request(verb::get, "/v1/jobs/abc/steps/.png", "")).result_int(), 404);
}

// solver.tolerance travels from the request to the solve, and the estimate back to the job,
// with the rays a pixel it chose (out of reach, it takes kToleranceAntialias where the
// camera's default is 2).
TEST(Api, AJobWithAToleranceReportsItsEstimatedError) {
  test::InProcessServer s(test::fresh_temp_dir("api-tolerance"));
  json scene = json::parse(test::small_scene_json(20));
  scene["solver"]["tolerance"] = 0.001;  // out of reach in 20 shots: the estimate is kept
  Response accepted = s.answer(request(verb::post, "/v1/jobs", json{{"scene", scene}}.dump()));
  ASSERT_EQ(accepted.result_int(), 202) << accepted.body();
  const std::string id = json::parse(accepted.body())["id"];
  s.wait_for(id, JobState::Done);
  const json job = json::parse(s.answer(request(verb::get, "/v1/jobs/" + id)).body());
  ASSERT_TRUE(job.contains("estimated_error")) << job.dump();
  EXPECT_GT(job["estimated_error"]["relative_rms"].get<double>(), 0);
  EXPECT_GT(job["estimated_error"]["standard_error"].get<double>(), 0);
  EXPECT_EQ(job["antialias"], SolverSettings::kToleranceAntialias);
}

TEST(Api, RetexturesRenderOnTheirPoolAndStopWhenAsked) {
  test::InProcessServer s(test::fresh_temp_dir("api"));
  Response accepted = s.answer(request(verb::post, "/v1/jobs", test::small_job_json(5, 5)));
  std::string id = json::parse(accepted.body())["id"];
  s.wait_for(id, JobState::Done);
  Request retexture = request(verb::post, "/v1/jobs/" + id + "/retexture", "{}");
  Routed routed = s.api.handle(retexture);
  ASSERT_TRUE(std::holds_alternative<DeferredRequest>(routed.action));
  EXPECT_EQ(std::get<DeferredRequest>(routed.action).pool, DeferredRequest::Pool::Render);
  EXPECT_EQ(s.answer(retexture).result_int(), 200);
  std::stop_source gone;
  gone.request_stop();  // the client hung up before the render began
  Response stopped = s.answer(retexture, gone);
  EXPECT_EQ(stopped.result_int(), 503);
  EXPECT_NE(detail(stopped).find("client went away"), std::string::npos);
}

TEST(Api, InternalErrorsTellNothingOfTheServer) {
  auto dir = test::fresh_temp_dir("api");
  std::string id;
  {
    test::InProcessServer s(dir);
    Response accepted = s.answer(request(verb::post, "/v1/jobs", test::small_job_json(5, 5)));
    id = json::parse(accepted.body())["id"];
    s.wait_for(id, JobState::Done);
  }
  // A damaged solution file on disk, and no copy in memory.
  test::InProcessServer restarted(dir);
  std::filesystem::resize_file(restarted.store.path(id, Artifact::Solution), 100);
  Response r = restarted.answer(request(verb::post, "/v1/jobs/" + id + "/retexture", "{}"));
  EXPECT_EQ(r.result_int(), 500);
  EXPECT_EQ(detail(r), "the server could not answer this request; its log says why");
  EXPECT_EQ(r.body().find(dir.string()), std::string::npos);
}

TEST(Api, MethodsNotAllowedListHead) {
  test::InProcessServer s(test::fresh_temp_dir("api"));
  Response r = s.answer(request(verb::put, "/v1/jobs"));
  EXPECT_EQ(r.result_int(), 405);
  EXPECT_EQ(r[http::field::allow], "GET, HEAD, POST");
  EXPECT_EQ(s.answer(request(verb::delete_, "/healthz"))[http::field::allow], "GET, HEAD");
}

// What the viewer needs: validation as a submit would do it, example scenes, drafts, downloads.
TEST(Api, ValidationExamplesDraftsAndDownloads) {
  test::InProcessServer s(test::fresh_temp_dir("api"));
  Response valid = s.answer(request(verb::post, "/v1/validate", test::small_job_json(5, 5)));
  ASSERT_EQ(valid.result_int(), 200) << valid.body();
  json v = json::parse(valid.body());
  EXPECT_EQ(v["valid"], true);
  EXPECT_GT(v["estimate"]["solve_s"].get<double>(), 0);
  EXPECT_EQ(v["estimate"]["limit_s"], 600);
  EXPECT_TRUE(s.store.list().empty()) << "validating queues nothing";
  json bad = json::parse(test::small_job_json(5, 5));
  bad["scene"]["objects"][2]["size"][1] = 0;
  Response invalid = s.answer(request(verb::post, "/v1/validate", bad.dump()));
  EXPECT_EQ(invalid.result_int(), 422);
  EXPECT_EQ(json::parse(invalid.body())["field"], "/scene/objects/2/size/1");

  Response example = s.answer(request(verb::get, "/v1/scenes/cornell"));
  ASSERT_EQ(example.result_int(), 200);
  EXPECT_TRUE(json::parse(example.body()).contains("objects"));
  EXPECT_EQ(s.answer(request(verb::get, "/v1/scenes/attic")).result_int(), 404);

  std::string id = json::parse(
      s.answer(request(verb::post, "/v1/jobs", test::small_job_json(5, 5))).body())["id"];
  s.wait_for(id, JobState::Done);
  Response solution = s.answer(request(verb::get, "/v1/jobs/" + id + "/solution"));
  ASSERT_EQ(solution.result_int(), 200);
  EXPECT_EQ(solution.body(), *s.store.read(id, Artifact::Solution));
  EXPECT_NE(solution[http::field::content_disposition].find(id + ".bumprad"), std::string::npos);
  Response draft = s.answer(request(verb::post, "/v1/jobs/" + id + "/retexture",
                                    R"({"quality": "draft", "format": "jpeg"})"));
  ASSERT_EQ(draft.result_int(), 200) << draft.body();
  EXPECT_EQ(draft[http::field::content_type], "image/jpeg");
  EXPECT_EQ(draft.body().substr(0, 3), std::string("\xff\xd8\xff", 3));
}

}  // namespace
}  // namespace bumprad
