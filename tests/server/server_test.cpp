// The HTTP service end to end: the real `bumprad serve` on a loopback port, driven with real
// HTTP through every endpoint. Jobs solve a small room in well under a second.
#include <sys/socket.h>
#include <unistd.h>

#include <arpa/inet.h>
#include <netinet/in.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <future>
#include <set>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clients/event_stream.h"
#include "tests/test_command.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using test::ServerProcess;

std::string submit(const HttpClient& c, const std::string& body) {
  HttpResponse r = c.request("POST", "/v1/jobs", body);
  EXPECT_EQ(r.status, 202) << r.body;
  std::string id = json::parse(r.body)["id"];
  EXPECT_EQ(r.header("location"), "/v1/jobs/" + id);
  return id;
}

// Width and height from a PNG's IHDR chunk.
std::pair<int, int> png_size(const std::string& png) {
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  auto be32 = [&](std::size_t at) {
    int v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(png[at + i]);
    return v;
  };
  return {be32(16), be32(20)};
}

void expect_problem(const HttpResponse& r, int status, const std::string& detail_part,
                    const std::string& field = "") {
  EXPECT_EQ(r.status, status) << r.body;
  EXPECT_EQ(r.header("content-type"), "application/problem+json");
  json p = json::parse(r.body);
  EXPECT_EQ(p["status"], status);
  EXPECT_TRUE(p["title"].is_string());
  EXPECT_NE(p["detail"].get<std::string>().find(detail_part), std::string::npos) << r.body;
  if (!field.empty()) {
    EXPECT_EQ(p.value("field", ""), field) << r.body;
  }
}

TEST(Server, SubmitWatchFetchAndRetexture) {
  ServerProcess server(test::fresh_temp_dir("server"));
  HttpClient c = server.client();
  EXPECT_EQ(c.get("/healthz").status, 200);
  std::string id = submit(c, test::small_job_json(40, 10));

  // Events: a first state at once, steps in order, then the end.
  EventStreamParser parser;
  std::vector<ServerEvent> events;
  HttpResponse head = c.stream("/v1/jobs/" + id + "/events", [&](std::string_view bytes) {
    for (auto& e : parser.feed(bytes)) events.push_back(e);
    return events.empty() || events.back().name == "state" || events.back().name == "step";
  });
  EXPECT_EQ(head.status, 200);
  EXPECT_EQ(head.header("content-type"), "text/event-stream");
  ASSERT_GE(events.size(), 2u);
  EXPECT_EQ(events.front().name, "state");
  EXPECT_EQ(events.back().name, "done");
  int last_step = 0;
  for (const auto& e : events)
    if (e.name == "step") {
      json step = json::parse(e.data);
      EXPECT_GT(step["step"].get<int>(), last_step);
      last_step = step["step"];
      EXPECT_EQ(step["preview"], "/v1/jobs/" + id + "/steps/" + std::to_string(last_step) + ".png");
    }
  // Drafts at 10, 20 and 30 shots (as many as fit in a quarter of the job's time; the first
  // always), then the final image.
  EXPECT_GE(last_step, 2);
  EXPECT_LE(last_step, 4);

  json job = json::parse(c.get("/v1/jobs/" + id).body);
  EXPECT_EQ(job["state"], "done");
  EXPECT_EQ(job["shots"], 40);
  EXPECT_EQ(job["step"], last_step);
  EXPECT_GT(job["elements"].get<int>(), 100);

  HttpResponse image = c.get("/v1/jobs/" + id + "/image");
  ASSERT_EQ(image.status, 200);
  EXPECT_EQ(image.header("content-type"), "image/png");
  EXPECT_EQ(png_size(image.body), std::make_pair(64, 48));
  EXPECT_EQ(image.header("content-disposition"), "inline; filename=\"" + id + ".png\"");
  HttpResponse exr = c.get("/v1/jobs/" + id + "/image?format=exr");
  EXPECT_EQ(exr.status, 200);
  EXPECT_EQ(exr.body.substr(0, 4), std::string("\x76\x2f\x31\x01", 4));
  EXPECT_EQ(exr.header("content-disposition"), "inline; filename=\"" + id + ".exr\"");

  // Steps: immutable per-step URLs; the latest preview is the final image.
  HttpResponse step1 = c.get("/v1/jobs/" + id + "/steps/1.png");
  EXPECT_EQ(step1.status, 200);
  EXPECT_NE(step1.header("cache-control").find("immutable"), std::string::npos);
  EXPECT_EQ(c.get("/v1/jobs/" + id + "/preview?step=1").body, step1.body);
  HttpResponse latest = c.get("/v1/jobs/" + id + "/preview");
  EXPECT_EQ(latest.header("x-bumprad-step"), std::to_string(last_step));
  EXPECT_EQ(latest.body, image.body);
  EXPECT_NE(step1.body, image.body) << "the first step is less converged";

  // Re-texture: new bumps and a new size from the kept map, no solve.
  HttpResponse same = c.request("POST", "/v1/jobs/" + id + "/retexture", "{}");
  ASSERT_EQ(same.status, 200) << same.body;
  EXPECT_EQ(same.body, image.body) << "no change re-renders the final image exactly";
  HttpResponse bricks = c.request(
      "POST", "/v1/jobs/" + id + "/retexture",
      R"({"bumps": {"wrinkles": {"type": "bricks", "amplitude": 0.02}}, "camera": {"width": 80}})");
  ASSERT_EQ(bricks.status, 200) << bricks.body;
  EXPECT_EQ(png_size(bricks.body), std::make_pair(80, 48));
  HttpResponse flat = c.request("POST", "/v1/jobs/" + id + "/retexture",
                                R"({"bumps": {"wrinkles": {"type": "bricks", "amplitude": 0}}})");
  EXPECT_NE(flat.body, image.body) << "bumps show in the image";
  EXPECT_EQ(c.request("POST", "/v1/jobs/" + id + "/retexture", "{}").body, image.body)
      << "the view kept from the re-textures before renders the final image exactly";
  expect_problem(c.request("POST", "/v1/jobs/" + id + "/retexture",
                           R"({"bumps": {"wrinkles": {"type": "brick"}}})"),
                 422, "unknown bump type", "/bumps/wrinkles/type");
  EXPECT_EQ(json::parse(c.get("/v1/jobs/" + id).body)["shots"], 40) << "nothing was re-solved";

  // The lit model (its content: gltf_export_test; its validity: gltf_validate_test).
  HttpResponse model = c.get("/v1/jobs/" + id + "/model.glb");
  ASSERT_EQ(model.status, 200) << model.body;
  EXPECT_EQ(model.header("content-type"), "model/gltf-binary");
  EXPECT_EQ(model.body.substr(0, 4), "glTF");
  EXPECT_NE(model.header("content-disposition").find(id + ".glb"), std::string::npos);

  json stored = json::parse(c.get("/v1/jobs/" + id + "/scene").body);
  EXPECT_EQ(stored["solver"]["preview_every"], 10) << "the request's settings are merged in";
  EXPECT_EQ(stored["bumps"]["wrinkles"]["type"], "wrinkles");

  // Listing, scenes, OpenAPI, the viewer page and metrics.
  json list = json::parse(c.get("/v1/jobs").body);
  ASSERT_EQ(list["jobs"].size(), 1u);
  EXPECT_EQ(list["jobs"][0]["id"], id);
  EXPECT_GE(json::parse(c.get("/v1/scenes").body)["scenes"].size(), 3u);
  json openapi = json::parse(c.get("/v1/openapi").body);
  EXPECT_TRUE(openapi["paths"].contains("/v1/jobs/{id}/retexture"));
  EXPECT_TRUE(openapi["paths"].contains("/v1/jobs/{id}/model.glb"));
  HttpResponse page = c.get("/");
  EXPECT_EQ(page.header("content-type"), "text/html; charset=utf-8");
  EXPECT_NE(page.body.find("viewer.js"), std::string::npos);
  std::string metrics = c.get("/metrics").body;
  EXPECT_NE(metrics.find("bumprad_jobs{state=\"done\"} 1"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("bumprad_shots_total 40"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("bumprad_http_requests_total{method=\"POST\",route=\"/v1/jobs/{id}/"
                         "retexture\",status=\"200\"} 4"),
            std::string::npos)
      << metrics;
  EXPECT_NE(metrics.find("bumprad_http_request_seconds_count{method=\"GET\",route=\"/v1/jobs\"}"),
            std::string::npos);

  EXPECT_EQ(server.terminate(), 0);
  EXPECT_NE(server.log().find("job " + id + " done"), std::string::npos) << "logs state changes";
  EXPECT_NE(server.log().find("GET /v1/jobs 200"), std::string::npos) << "logs requests";
}

// A multipart/x-mixed-replace stream: one PNG part per step, the final image last, then the
// closing boundary, so a plain <img> ends on the finished picture.
TEST(Server, ImageStreamEndsWithTheFinalImage) {
  ServerProcess server(test::fresh_temp_dir("server"));
  HttpClient c = server.client();
  std::string id = submit(c, test::small_job_json(30, 10));
  std::string body;
  HttpResponse head = c.stream("/v1/jobs/" + id + "/stream", [&](std::string_view b) {
    body += b;
    return true;
  });
  EXPECT_EQ(head.header("content-type"), "multipart/x-mixed-replace; boundary=bumpradframe");
  std::vector<std::string> parts;
  for (std::size_t at = 0; (at = body.find("Content-Length: ", at)) != std::string::npos;) {
    std::size_t length = std::stoul(body.substr(at + 16));
    std::size_t start = body.find("\r\n\r\n", at) + 4;
    parts.push_back(body.substr(start, length));
    at = start + length;
  }
  ASSERT_GE(parts.size(), 1u);
  EXPECT_TRUE(body.ends_with("--bumpradframe--\r\n"));
  EXPECT_EQ(parts.back(), c.get("/v1/jobs/" + id + "/image").body);
  for (const auto& p : parts) EXPECT_EQ(png_size(p), std::make_pair(64, 48));
}

TEST(Server, CancelStopsARunningJobAndDeleteRemovesIt) {
  fs::path data = test::fresh_temp_dir("server");
  ServerProcess server(data);
  HttpClient c = server.client();
  std::string id = submit(c, test::small_job_json(0, 50, /*endless=*/true));
  test::wait_for_job(c, id, {"running"});
  HttpResponse cancel = c.request("DELETE", "/v1/jobs/" + id);
  EXPECT_EQ(cancel.status, 202) << cancel.body;
  json job = json::parse(test::wait_for_job(c, id, {"cancelled"}, 10));
  EXPECT_LT(job["shots"].get<int>(), 1'000'000);
  expect_problem(c.get("/v1/jobs/" + id + "/image"), 409, "is cancelled");
  EXPECT_TRUE(fs::exists(data / "jobs" / id));

  EXPECT_EQ(c.request("DELETE", "/v1/jobs/" + id).status, 204);
  expect_problem(c.get("/v1/jobs/" + id), 404, "no job with id");
  EXPECT_FALSE(fs::exists(data / "jobs" / id)) << "its files went with it";
}

TEST(Server, AFullQueueAnswers429WithRetryAfter) {
  ServerProcess server(test::fresh_temp_dir("server"), {"--workers", "1", "--max-queue", "1"});
  HttpClient c = server.client();
  std::string running = submit(c, test::small_job_json(0, 50, true));
  test::wait_for_job(c, running, {"running"});
  std::string waiting = submit(c, test::small_job_json(10, 5));
  HttpResponse full = c.request("POST", "/v1/jobs", test::small_job_json(10, 5));
  expect_problem(full, 429, "already waiting");
  EXPECT_EQ(full.header("retry-after"), "5");
  EXPECT_EQ(json::parse(c.get("/v1/jobs/" + waiting).body)["state"], "queued");
  EXPECT_NE(c.get("/metrics").body.find("bumprad_queue_depth 1"), std::string::npos);

  // Cancelling the queued job frees its place; cancelling the running one lets the next run.
  EXPECT_EQ(c.request("DELETE", "/v1/jobs/" + waiting).status, 202);
  EXPECT_EQ(json::parse(c.get("/v1/jobs/" + waiting).body)["state"], "cancelled");
  std::string next = submit(c, test::small_job_json(10, 5));
  EXPECT_EQ(c.request("DELETE", "/v1/jobs/" + running).status, 202);
  test::wait_for_job(c, next, {"done"});
}

TEST(Server, BadRequestsGetProblemDetailsAndTheServerCarriesOn) {
  ServerProcess server(test::fresh_temp_dir("server"), {"--body-limit", "4K"});
  HttpClient c = server.client();
  expect_problem(c.request("POST", "/v1/jobs", std::string(5000, ' ')), 413, "4096 bytes");
  expect_problem(c.request("POST", "/v1/jobs", "{\"builtin\": "), 400, "malformed JSON");
  expect_problem(c.request("POST", "/v1/jobs", R"({"builtin": "attic"})"), 422,
                 "unknown built-in scene", "/builtin");
  json bad = json::parse(test::small_job_json(10, 5));
  bad["scene"]["objects"][0]["size"][1] = -3;
  expect_problem(c.request("POST", "/v1/jobs", bad.dump()), 422, "greater than 0",
                 "/scene/objects/0/size/1");
  bad = json::parse(test::small_job_json(10, 5));
  bad["scene"]["bumps"]["wrinkles"] = {{"type", "image"}, {"file", "/etc/passwd"}};
  expect_problem(c.request("POST", "/v1/jobs", bad.dump()), 422, "cannot be named here",
                 "/scene/bumps/wrinkles/file");
  expect_problem(c.get("/v2/jobs"), 404, "no such resource");
  expect_problem(c.get("/v1/jobs/../../etc"), 404, "no such resource");
  expect_problem(c.get("/v1/jobs/..%2F..%2Fetc"), 404, "no job with id");
  expect_problem(c.get("/v1/jobs/0123456789abcdef"), 404, "no job with id");
  HttpResponse wrong = c.request("PUT", "/v1/jobs");
  expect_problem(wrong, 405, "PUT is not allowed");
  EXPECT_EQ(wrong.header("allow"), "GET, HEAD, POST");
  expect_problem(c.request("DELETE", "/healthz"), 405, "DELETE");

  std::string id = submit(c, test::small_job_json(0, 50, true));
  test::wait_for_job(c, id, {"running"});
  expect_problem(c.get("/v1/jobs/" + id + "/image"), 409, "is running");
  expect_problem(c.request("POST", "/v1/jobs/" + id + "/retexture", "{}"), 409, "is running");
  expect_problem(c.get("/v1/jobs/" + id + "/image?format=tiff"), 400, "png or exr", "format");
  expect_problem(c.get("/v1/jobs/" + id + "/preview?step=x"), 400, "integer", "step");
  expect_problem(c.get("/v1/jobs/" + id + "/steps/999.png"), 404, "has no step 999");

  // Garbage on a raw socket, and a client that hangs up mid-request.
  for (const std::string& junk :
       {std::string("NOT HTTP AT ALL\r\n\r\n"),
        std::string("POST /v1/jobs HTTP/1.1\r\nContent-Length: 99\r\n")}) {
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(server.port());
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    ASSERT_EQ(write(fd, junk.data(), junk.size()), ssize_t(junk.size()));
    shutdown(fd, SHUT_WR);
    char reply[512] = {};
    ssize_t n = read(fd, reply, sizeof reply - 1);
    close(fd);
    std::string answer(reply, std::size_t(std::max<ssize_t>(n, 0)));
    if (junk.starts_with("NOT")) {
      EXPECT_NE(answer.find(" 400 "), std::string::npos) << answer;
    }
  }
  EXPECT_EQ(c.get("/healthz").status, 200);
  EXPECT_EQ(c.request("DELETE", "/v1/jobs/" + id).status, 202);
}

// Re-textures beyond --max-retextures are refused at once instead of queueing their bodies.
// The slow re-texture (1024 x 1024 at 4 x 4 rays a pixel: about 50 s on the 2-core machine)
// is cut by its 2 s time limit, whatever the machine: nothing here waits for it to finish.
TEST(Server, ReTexturesBeyondTheLimitGet503) {
  ServerProcess server(test::fresh_temp_dir("server"),
                       {"--max-retextures", "1", "--retexture-timeout", "2"});
  HttpClient c = server.client();
  std::string id = submit(c, test::small_job_json(5, 5));
  test::wait_for_job(c, id, {"done"});
  auto slow = std::async(std::launch::async, [&] {
    return c.request("POST", "/v1/jobs/" + id + "/retexture",
                     R"({"camera": {"width": 1024, "height": 1024, "antialias": 4}})");
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  HttpResponse busy = c.request("POST", "/v1/jobs/" + id + "/retexture", "{}");
  expect_problem(busy, 503, "already waiting");
  EXPECT_EQ(busy.header("retry-after"), "1");
  expect_problem(slow.get(), 503, "time limit");
  EXPECT_EQ(c.request("POST", "/v1/jobs/" + id + "/retexture", "{}").status, 200);
}

TEST(Server, ConcurrentSubmissionsAllRun) {
  ServerProcess server(test::fresh_temp_dir("server"), {"--workers", "2", "--max-queue", "16"});
  HttpClient c = server.client();
  std::vector<std::future<std::string>> submits;
  for (int i = 0; i < 8; ++i)
    submits.push_back(std::async(std::launch::async,
                                 [&, i] { return submit(c, test::small_job_json(10 + i, 5)); }));
  std::set<std::string> ids;
  for (auto& f : submits) ids.insert(f.get());
  EXPECT_EQ(ids.size(), 8u);
  for (const std::string& id : ids) {
    json job = json::parse(test::wait_for_job(c, id, {"done", "failed"}));
    EXPECT_EQ(job["state"], "done") << job.dump();
  }
}

// kill -9 loses nothing that was finished: done jobs are served and re-texturable again,
// the job that was running is marked interrupted and the queued one runs.
TEST(Server, RestartAfterSigkillKeepsFinishedJobs) {
  fs::path data = test::fresh_temp_dir("server");
  std::string done, running, queued, image;
  {
    ServerProcess server(data, {"--workers", "1"});
    HttpClient c = server.client();
    done = submit(c, test::small_job_json(20, 10));
    test::wait_for_job(c, done, {"done"});
    image = c.get("/v1/jobs/" + done + "/image").body;
    running = submit(c, test::small_job_json(0, 20, true));
    test::wait_for_job(c, running, {"running"});
    while (json::parse(c.get("/v1/jobs/" + running).body)["step"] < 2)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    queued = submit(c, test::small_job_json(10, 5));
    server.kill_hard();
  }
  // What a write cut short by the kill leaves: its temporary file.
  const fs::path orphan = data / "jobs" / done / ".image.tmp-4242-0.png";
  const fs::path orphan_step = data / "jobs" / running / "steps" / ".9.tmp-4242-1.png";
  std::ofstream(orphan) << "half";
  std::ofstream(orphan_step) << "half";
  ServerProcess server(data, {"--workers", "1"});
  EXPECT_FALSE(fs::exists(orphan));
  EXPECT_FALSE(fs::exists(orphan_step));
  HttpClient c = server.client();
  EXPECT_EQ(json::parse(c.get("/v1/jobs/" + done).body)["state"], "done");
  EXPECT_EQ(c.get("/v1/jobs/" + done + "/image").body, image);
  HttpResponse re = c.request("POST", "/v1/jobs/" + done + "/retexture", "{}");
  EXPECT_EQ(re.status, 200) << re.body;
  EXPECT_EQ(re.body, image) << "the map and radiosity came back from disk exactly";
  json interrupted = json::parse(c.get("/v1/jobs/" + running).body);
  EXPECT_EQ(interrupted["state"], "interrupted");
  EXPECT_NE(interrupted["error"].get<std::string>().find("submit it again"), std::string::npos);
  // Its steps are still there and the record says so, though it was not rewritten per step.
  int step = interrupted["step"];
  EXPECT_GE(step, 2);
  EXPECT_EQ(c.get("/v1/jobs/" + running + "/steps/" + std::to_string(step) + ".png").status, 200);
  EXPECT_EQ(json::parse(test::wait_for_job(c, queued, {"done"}))["shots"], 10);
}

// A multipart/form-data body: each part (name, filename, bytes); no filename, a plain field.
std::string form(const std::string& boundary,
                 const std::vector<std::tuple<std::string, std::string, std::string>>& parts) {
  std::string body;
  for (const auto& [name, filename, bytes] : parts) {
    body += "--" + boundary + "\r\nContent-Disposition: form-data; name=\"" + name + "\"";
    if (!filename.empty()) body += "; filename=\"" + filename + "\"";
    body += "\r\nContent-Type: application/octet-stream\r\n\r\n" + bytes + "\r\n";
  }
  return body + "--" + boundary + "--\r\n";
}

// Jobs carry their models: a form of scene JSON and the glTF's files (the real test model's
// .gltf, .bin and texture), a bare .glb; the stored job keeps them, so a restarted server
// re-textures from disk with nothing in an asset directory.
TEST(Server, JobsCarryTheirModelsAcrossARestart) {
  const fs::path data = test::fresh_temp_dir("server");
  const fs::path box = test::kTestModels / "glTF2/BoxTextured-glTF";
  const std::string scene = R"({
    "camera": {"position": [2, 1.5, 3], "look_at": [0, 0, 0], "width": 48, "height": 36},
    "materials": {"lamp": {"reflectance": 0, "emission": 20}},
    "objects": [
      {"type": "model", "file": "BoxTextured.gltf"},
      {"type": "quad", "material": "lamp",
       "vertices": [[-1, 2, -1], [-1, 2, 1], [1, 2, 1], [1, 2, -1]]}],
    "solver": {"max_shots": 30}})";
  const std::string body =
      form("bumprad-test-boundary",
           {{"scene", "", scene},
            {"file", "BoxTextured.gltf", test::read_file(box / "BoxTextured.gltf")},
            {"file", "BoxTextured0.bin", test::read_file(box / "BoxTextured0.bin")},
            {"file", "CesiumLogoFlat.png", test::read_file(box / "CesiumLogoFlat.png")}});
  const std::string multipart = "multipart/form-data; boundary=bumprad-test-boundary";
  std::string id, image;
  {
    ServerProcess server(data, {"--workers", "1"});
    HttpClient c = server.client();
    HttpResponse r = c.request("POST", "/v1/jobs", body, multipart);
    ASSERT_EQ(r.status, 202) << r.body;
    id = json::parse(r.body)["id"];
    // What the importer assumed comes back with the job, naming the field and the file.
    const json warnings = json::parse(r.body)["warnings"];
    ASSERT_TRUE(warnings.is_array()) << r.body;
    EXPECT_EQ(
        warnings[0],
        "/scene/objects/0: \"BoxTextured.gltf\": material \"Texture\": base colour above 0.99 "
        "read as 0.99");
    ASSERT_EQ(json::parse(test::wait_for_job(c, id, {"done", "failed"}))["state"], "done");
    image = c.get("/v1/jobs/" + id + "/image").body;
    EXPECT_EQ(png_size(image), std::make_pair(48, 36));
    // Missing a file the model names: refused at once, naming it.
    const std::string without_texture =
        form("b", {{"scene", "", scene},
                   {"file", "BoxTextured.gltf", test::read_file(box / "BoxTextured.gltf")},
                   {"file", "BoxTextured0.bin", test::read_file(box / "BoxTextured0.bin")}});
    expect_problem(
        c.request("POST", "/v1/jobs", without_texture, "multipart/form-data; boundary=b"), 422,
        "texture \"CesiumLogoFlat.png\" is missing", "/scene/objects/0/file");
    expect_problem(c.request("POST", "/v1/jobs", body, "multipart/form-data; boundary=other"), 400,
                   "the form's boundary never appears");
    expect_problem(c.request("POST", "/v1/jobs", "solid box", "text/plain"), 415,
                   "a job is application/json, model/gltf-binary");
    // A bare .glb: the scene of that model (no emitter, so black, but solved and rendered).
    r = c.request(
        "POST", "/v1/jobs",
        test::read_file(test::kTestModels / "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"),
        "model/gltf-binary");
    ASSERT_EQ(r.status, 202) << r.body;
    const std::string glb = json::parse(r.body)["id"];
    EXPECT_EQ(json::parse(test::wait_for_job(c, glb, {"done", "failed"}))["state"], "done");
    server.kill_hard();
  }
  ServerProcess server(data, {"--workers", "1"});
  HttpClient c = server.client();
  HttpResponse re = c.request("POST", "/v1/jobs/" + id + "/retexture", "{}");
  ASSERT_EQ(re.status, 200) << re.body;
  EXPECT_EQ(re.body, image) << "the model came back from the stored job";
}

// SIGTERM: the running job stops within a shot, is recorded as interrupted, its event
// stream hears so, and the server exits cleanly.
TEST(Server, GracefulShutdownInterruptsRunningJobs) {
  fs::path data = test::fresh_temp_dir("server");
  std::string id;
  {
    ServerProcess server(data);
    HttpClient c = server.client();
    id = submit(c, test::small_job_json(0, 20, true));
    test::wait_for_job(c, id, {"running"});
    std::promise<void> connected;
    auto last_event = std::async(std::launch::async, [&] {
      EventStreamParser parser;
      std::string name;
      c.stream("/v1/jobs/" + id + "/events", [&](std::string_view b) {
        for (auto& e : parser.feed(b)) {
          if (e.name == "state") connected.set_value();
          name = e.name;
        }
        return true;
      });
      return name;
    });
    connected.get_future().wait();
    EXPECT_EQ(server.terminate(), 0);
    EXPECT_EQ(last_event.get(), "interrupted");
  }
  ServerProcess server(data);
  EXPECT_EQ(json::parse(server.client().get("/v1/jobs/" + id).body)["state"], "interrupted");
}

TEST(Server, OnlyTheNewestStepsAreKept) {
  fs::path data = test::fresh_temp_dir("server");
  ServerProcess server(data, {"--keep-steps", "1"});
  HttpClient c = server.client();
  std::string id = submit(c, test::small_job_json(20, 5));
  json job = json::parse(test::wait_for_job(c, id, {"done"}));
  int last = job["step"];
  ASSERT_GE(last, 2) << "a draft and the final image";
  EXPECT_EQ(job["first_kept_step"], last);
  expect_problem(c.get("/v1/jobs/" + id + "/steps/1.png"), 410, "no longer kept");
  EXPECT_FALSE(fs::exists(data / "jobs" / id / "steps" / "1.png"));
  EXPECT_EQ(c.get("/v1/jobs/" + id + "/steps/" + std::to_string(last) + ".png").status, 200);
}

TEST(Server, ASecondServerCannotShareTheDataDirectory) {
  fs::path data = test::fresh_temp_dir("server");
  ServerProcess first(data);
  auto second =
      test::run_command(std::string(BUMPRAD_BIN) + " serve --port 0 --data-dir " + data.string());
  EXPECT_EQ(second.exit_code, 1);
  EXPECT_NE(second.output.find("is in use by another bumprad serve"), std::string::npos)
      << second.output;
  EXPECT_EQ(first.client().get("/healthz").status, 200);
}

TEST(Server, RetentionEvictsWholeJobsLeastRecentlyUsedFirst) {
  fs::path data = test::fresh_temp_dir("server");
  ServerProcess server(data, {"--max-jobs", "2"});
  HttpClient c = server.client();
  std::vector<std::string> ids;
  for (int i = 0; i < 2; ++i) {
    ids.push_back(submit(c, test::small_job_json(5, 5)));
    test::wait_for_job(c, ids.back(), {"done"});
  }
  c.get("/v1/jobs/" + ids[0] + "/image");  // the first is now the more recently used
  ids.push_back(submit(c, test::small_job_json(5, 5)));
  test::wait_for_job(c, ids.back(), {"done"});
  EXPECT_EQ(c.get("/v1/jobs/" + ids[0]).status, 200);
  EXPECT_EQ(c.get("/v1/jobs/" + ids[1]).status, 404);
  EXPECT_FALSE(fs::exists(data / "jobs" / ids[1]));
  EXPECT_EQ(c.get("/v1/jobs/" + ids[2]).status, 200);
}

}  // namespace
}  // namespace bumprad
