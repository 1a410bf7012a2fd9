// The service under hostile input and faults, through real sockets against the real
// `bumprad serve`: requests built to crash it, hold it hostage or confuse its parser each get
// a clear answer, and the server keeps serving everyone else.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "solver/util/image.h"
#include "tests/raw_connection.h"
#include "tests/test_command.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

using json = nlohmann::json;
using test::RawConnection;
using test::ServerProcess;

void expect_problem(const HttpResponse& r, int status, const std::string& detail_part,
                    const std::string& field = "") {
  EXPECT_EQ(r.status, status) << r.body;
  EXPECT_EQ(r.header("content-type"), "application/problem+json");
  json p = json::parse(r.body);
  EXPECT_NE(p["detail"].get<std::string>().find(detail_part), std::string::npos) << r.body;
  if (!field.empty()) {
    EXPECT_EQ(p.value("field", ""), field) << r.body;
  }
}

std::string nested(const std::string& open, const std::string& close, int depth) {
  std::string s;
  for (int i = 0; i < depth; ++i) s += open;
  s += "1";
  for (int i = 0; i < depth; ++i) s += close;
  return s;
}

// Before: ~600 KB of brackets under "scene", "solver" or "preview_every" overflowed the
// stack when the value was copied, and the server died with every stream it had.
TEST(HostileInput, DeeplyNestedJsonGets400AndTheServerLives) {
  ServerProcess server(test::fresh_temp_dir("hostile"));
  HttpClient c = server.client();
  for (const std::string key : {"scene", "solver", "preview_every", "bumps"})
    for (const auto& [open, close] :
         {std::pair<std::string, std::string>{"[", "]"}, {"{\"a\":", "}"}}) {
      std::string body = "{\"" + key + "\": " + nested(open, close, 150000) + "}";
      expect_problem(c.request("POST", "/v1/jobs", body), 400, "nested deeper than 32");
    }
  EXPECT_EQ(c.get("/healthz").status, 200);
}

// Before: a request path or body with bytes that are not UTF-8 got 500 (the message quoting
// them could not be written as JSON).
TEST(HostileInput, InvalidUtf8IsQuotedEscaped) {
  ServerProcess server(test::fresh_temp_dir("hostile"));
  HttpClient c = server.client();
  expect_problem(c.request("POST", "/v1/jobs", "{\"builtin\": \"\xff\xfe\"}"), 400,
                 "malformed JSON");
  expect_problem(c.request("POST", "/v1/jobs", "\xc0\xaf"), 400, "malformed JSON");
  HttpResponse r = c.get("/v1/\xff\xc3(x");
  expect_problem(r, 404, "/v1/\\xFF\\xC3(x");
  EXPECT_EQ(c.get("/v1/jobs/\xe2\x82").status, 404);
  EXPECT_EQ(c.get("/healthz").status, 200);
}

// Before: the bytes of a second request that arrived with the first were thrown away, so
// pipelined requests went unanswered or were parsed from their middle.
TEST(HostileInput, PipelinedRequestsAreAllAnsweredInOrder) {
  ServerProcess server(test::fresh_temp_dir("hostile"));
  RawConnection raw(server.port());
  raw.send(
      "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n"
      "GET /v1/jobs/0123456789abcdef HTTP/1.1\r\nHost: x\r\n\r\n"
      "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Length: 2\r\n\r\n{}"
      "GET /v1/scenes HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  auto replies = test::split_responses(raw.read_all());
  ASSERT_EQ(replies.size(), 4u);
  EXPECT_EQ(replies[0].status, 200);
  EXPECT_EQ(replies[0].body, "{\"status\":\"ok\",\"store\":\"ok\"}");
  EXPECT_EQ(replies[1].status, 404);
  EXPECT_EQ(replies[2].status, 422);
  EXPECT_EQ(replies[3].status, 200);
  EXPECT_NE(replies[3].body.find("wrinkled-box"), std::string::npos);
}

// Before: curl, which sends `Expect: 100-continue` with any body over 1 KiB, waited a second
// for a 100 that never came before sending each large job. A body over the limit is refused
// from its header, before it is sent.
TEST(HostileInput, ABodyThatWaitsForContinueGetsItOrA413) {
  ServerProcess server(test::fresh_temp_dir("hostile"), {"--body-limit", "4K"});
  const std::string body = R"({"builtin": "attic"})";
  RawConnection raw(server.port());
  raw.send("POST /v1/jobs HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\nContent-Length: " +
           std::to_string(body.size()) + "\r\n\r\n");
  EXPECT_EQ(raw.read_all(5, "\r\n\r\n"), "HTTP/1.1 100 Continue\r\n\r\n");
  raw.send(body);
  auto replies = test::split_responses(raw.read_all(10, "}"));
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(replies[0].status, 422);
  EXPECT_NE(replies[0].body.find("unknown built-in scene"), std::string::npos);

  RawConnection large(server.port());
  large.send(
      "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\nContent-Length: "
      "5000\r\n\r\n");
  auto refused = test::split_responses(large.read_all(5));
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_EQ(refused[0].status, 413);
  EXPECT_NE(refused[0].body.find("4096 bytes"), std::string::npos);
}

// Before: HEAD got 405 with a body.
TEST(HostileInput, HeadAnswersAsGetWithoutTheBody) {
  ServerProcess server(test::fresh_temp_dir("hostile"));
  HttpResponse get = server.client().get("/v1/scenes");
  RawConnection raw(server.port());
  raw.send(
      "HEAD /v1/scenes HTTP/1.1\r\nHost: x\r\n\r\n"
      "HEAD /v1/jobs/0123456789abcdef/events HTTP/1.1\r\nHost: x\r\n\r\n"
      "GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  auto replies = test::split_responses(raw.read_all(), {true, true, false});
  ASSERT_EQ(replies.size(), 3u);
  EXPECT_EQ(replies[0].status, 200);
  EXPECT_NE(replies[0].head.find("Content-Length: " + std::to_string(get.body.size())),
            std::string::npos)
      << replies[0].head;
  EXPECT_EQ(replies[0].body, "") << "no body came after the head";
  EXPECT_EQ(replies[1].status, 404);
  EXPECT_EQ(replies[2].status, 200);
  EXPECT_EQ(replies[2].body, "{\"status\":\"ok\",\"store\":\"ok\"}");
}

std::string submit(const HttpClient& c, const std::string& body) {
  HttpResponse r = c.request("POST", "/v1/jobs", body);
  EXPECT_EQ(r.status, 202) << r.body;
  return json::parse(r.body).value("id", "");
}

// A camera whose final render takes tens of seconds here (2048^2 pixels, 9 rays each, none
// sampled again), yet is estimated under the default limits.
json slow_camera() {
  return {{"width", 2048}, {"height", 2048}, {"antialias", 3}, {"antialias_max", 3}};
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Before: a 561-byte job held the only worker for hours, and a re-texture of 8192^2 pixels
// at 8x8 antialiasing and 256 glossy samples took hours of every core. (A million shots
// allowed is not in itself too much: a solve stops at its unshot target, cornell's after
// about 1,000; an unshot target of 0 spends them all.)
TEST(HostileInput, WorkOverTheCostLimitIsRefusedBeforeItStarts) {
  ServerProcess server(test::fresh_temp_dir("hostile"));
  HttpClient c = server.client();
  json job = json::parse(test::small_job_json(10, 5));
  job["scene"]["solver"] = {{"element_size", 0.03},
                            {"hemicube_resolution", 1024},
                            {"max_shots", 1000000},
                            {"unshot_fraction", 0}};
  expect_problem(c.request("POST", "/v1/jobs", job.dump()), 422,
                 "over this server's limit of 10 min", "/scene/solver");
  expect_problem(
      c.request(
          "POST", "/v1/jobs",
          R"({"builtin": "cornell", "solver": {"max_shots": 1000000, "unshot_fraction": 0}})"),
      422, "to solve (2,305 elements, 632 patches, about 1,000,000 shots", "/solver");
  job = json::parse(test::small_job_json(5, 5));
  job["scene"]["camera"]["width"] = job["scene"]["camera"]["height"] = 8192;
  job["scene"]["camera"]["antialias"] = 8;
  job["scene"]["materials"]["green"] = {{"reflectance", 0.3}, {"specular", 0.5}, {"shininess", 50}};
  expect_problem(c.request("POST", "/v1/jobs", job.dump()), 422, "to render (8,192x8,192 pixels",
                 "/scene/camera");

  std::string id = submit(c, test::small_job_json(5, 5));
  test::wait_for_job(c, id, {"done"});
  HttpResponse r = c.request(
      "POST", "/v1/jobs/" + id + "/retexture",
      R"({"camera": {"width": 8192, "height": 8192, "antialias": 8, "glossy_samples": 256}})");
  expect_problem(r, 422, "over this server's limit of 30 s", "/camera");
  EXPECT_EQ(c.request("POST", "/v1/jobs/" + id + "/retexture", "{}").status, 200);
}

// Before: nothing stopped a job or a re-texture that ran long; DELETE answered 202 while
// the final render went on, and a client that hung up did not stop its re-texture.
TEST(HostileInput, TimeLimitsCancelsAndHangUpsStopRenders) {
  ServerProcess server(test::fresh_temp_dir("hostile"),
                       {"--job-timeout", "2", "--retexture-timeout", "1", "--workers", "2"});
  HttpClient c = server.client();
  std::string done = submit(c, test::small_job_json(5, 5));
  test::wait_for_job(c, done, {"done"});

  // A job past its wall time fails, saying why.
  std::string endless = submit(c, test::small_job_json(0, 50, true));
  json failed = json::parse(test::wait_for_job(c, endless, {"failed"}, 15));
  EXPECT_NE(failed["error"].get<std::string>().find("time limit of 2 s"), std::string::npos)
      << failed.dump();

  // A re-texture past its wall time is stopped within a row: 503, not tens of seconds.
  const std::string slow = json{{"camera", slow_camera()}}.dump();
  auto t = std::chrono::steady_clock::now();
  expect_problem(c.request("POST", "/v1/jobs/" + done + "/retexture", slow), 503,
                 "time limit of 1 s");
  EXPECT_LT(seconds_since(t), 5);

  // DELETE during the final render stops it (on a server whose time limit is far away).
  ServerProcess roomy(test::fresh_temp_dir("hostile-roomy"));
  HttpClient r = roomy.client();
  json job = json::parse(test::small_job_json(10, 10));
  job["scene"]["camera"].update(slow_camera());
  std::string rendering = submit(r, job.dump());
  test::wait_for_job(r, rendering, {"running"});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // past the solve's 10 shots
  t = std::chrono::steady_clock::now();
  EXPECT_EQ(r.request("DELETE", "/v1/jobs/" + rendering).status, 202);
  test::wait_for_job(r, rendering, {"cancelled"}, 5);
  EXPECT_LT(seconds_since(t), 5);

  // A client that hangs up stops its re-texture: the log has its end within seconds.
  auto stopped_retextures = [&] {
    std::string log = server.log();
    int n = 0;
    for (std::size_t at = 0; (at = log.find("/retexture 503", at)) != std::string::npos; ++at) ++n;
    return n;
  };
  const int before = stopped_retextures();
  {
    RawConnection raw(server.port());
    raw.send("POST /v1/jobs/" + done + "/retexture HTTP/1.1\r\nHost: x\r\nContent-Length: " +
             std::to_string(slow.size()) + "\r\n\r\n" + slow);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  t = std::chrono::steady_clock::now();
  while (stopped_retextures() == before && seconds_since(t) < 0.9)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(stopped_retextures(), before + 1)
      << "not stopped before its 1 s limit: " << server.log();
}

// Before: SIGTERM waited for renders in progress, far past its 3 s grace.
TEST(HostileInput, SigtermEndsRendersWithinTheGrace) {
  ServerProcess server(test::fresh_temp_dir("hostile"), {"--workers", "1"});
  HttpClient c = server.client();
  std::string done = submit(c, test::small_job_json(5, 5));
  test::wait_for_job(c, done, {"done"});
  json job = json::parse(test::small_job_json(10, 10));
  job["scene"]["camera"].update(slow_camera());
  std::string rendering = submit(c, job.dump());
  auto retexture = std::async(std::launch::async, [&] {
    return c.request("POST", "/v1/jobs/" + done + "/retexture",
                     json{{"camera", slow_camera()}}.dump());
  });
  test::wait_for_job(c, rendering, {"running"});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  auto t = std::chrono::steady_clock::now();
  EXPECT_EQ(server.terminate(), 0);
  EXPECT_LT(seconds_since(t), 5);
  HttpResponse answered = retexture.get();
  EXPECT_EQ(answered.status, 503) << answered.body;
}

// Before: a FIFO named as an image inside --assets blocked a network thread for good, and
// even /healthz stopped answering.
TEST(HostileInput, AFifoInTheAssetsIsRefused) {
  namespace fs = std::filesystem;
  fs::path assets = test::fresh_temp_dir("hostile-assets");
  ASSERT_EQ(mkfifo((assets / "pipe.png").c_str(), 0644), 0);
  ServerProcess server(test::fresh_temp_dir("hostile"), {"--assets", assets.string()});
  HttpClient c = server.client();
  json job = json::parse(test::small_job_json(5, 5));
  job["scene"]["bumps"]["wrinkles"] = {{"type", "image"}, {"file", "pipe.png"}};
  expect_problem(c.request("POST", "/v1/jobs", job.dump()), 422, "is not a regular file",
                 "/scene/bumps/wrinkles/file");
  EXPECT_EQ(c.get("/healthz").status, 200);
}

// Before: a scene could name any number of images up to 8192^2 each, and the server decoded
// them all (4.4 GB for one 16384^2 PNG before the pixel limit). Now one scene's images share
// --max-image-memory, checked from each header before its pixels are decoded.
TEST(HostileInput, AScenesImagesAreBoundedTogether) {
  namespace fs = std::filesystem;
  fs::path assets = test::fresh_temp_dir("hostile-assets");
  Image grey(512, 512);  // 8-bit RGB: keeps 3.1 MB of floats, 3.9 MB while it decodes
  std::fill(grey.rgb.begin(), grey.rgb.end(), 0.5f);
  write_image(assets / "a.png", grey, 1);
  write_image(assets / "b.png", grey, 1);
  ServerProcess server(test::fresh_temp_dir("hostile"),
                       {"--assets", assets.string(), "--max-image-memory", "5M"});
  HttpClient c = server.client();
  json job = json::parse(test::small_job_json(5, 5));
  job["scene"]["bumps"]["wrinkles"] = {{"type", "image"}, {"file", "a.png"}};
  EXPECT_EQ(c.request("POST", "/v1/validate", job.dump()).status, 200);
  job["scene"]["materials"]["wall"] = {{"texture", {{"type", "image"}, {"file", "b.png"}}}};
  expect_problem(c.request("POST", "/v1/validate", job.dump()), 422,
                 "cannot read image: a.png: 512 x 512 pixels take 4 MB to decode, over what is "
                 "left of the 6 MB one scene's images may take (4 MB taken by the images before "
                 "it)",
                 "/scene/bumps/wrinkles/file");
  EXPECT_EQ(c.get("/healthz").status, 200);
}

// Before: with no descriptors left, accept failed at once, again and again, at a full core,
// and new clients hung. Now it backs off, and clients beyond --max-connections get 503.
TEST(HostileInput, RunningOutOfDescriptorsBacksOff) {
  ServerProcess server(test::fresh_temp_dir("hostile"), {}, {"prlimit", "--nofile=48"});
  std::vector<std::unique_ptr<RawConnection>> hogs;
  for (int i = 0; i < 80; ++i) hogs.push_back(std::make_unique<RawConnection>(server.port()));
  auto cpu_seconds = [&] {
    std::ifstream stat("/proc/" + std::to_string(server.pid()) + "/stat");
    std::string field;
    for (int i = 0; i < 13; ++i) stat >> field;
    long utime = 0, stime = 0;
    stat >> utime >> stime;
    return double(utime + stime) / double(sysconf(_SC_CLK_TCK));
  };
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  double before = cpu_seconds();
  std::this_thread::sleep_for(std::chrono::seconds(2));
  EXPECT_LT(cpu_seconds() - before, 0.5) << "the accept loop spins";
  std::string log = server.log();
  std::size_t reports = 0;
  for (std::size_t at = 0; (at = log.find("accept: ", at)) != std::string::npos; ++at) ++reports;
  EXPECT_GE(reports, 1u);
  EXPECT_LE(reports, 2u) << log;
  hogs.clear();
  EXPECT_EQ(server.client(5).get("/healthz").status, 200);
}

TEST(HostileInput, ConnectionsBeyondTheCapGet503) {
  ServerProcess server(test::fresh_temp_dir("hostile"), {"--max-connections", "2"});
  auto first = std::make_unique<RawConnection>(server.port());
  RawConnection second(server.port());
  RawConnection third(server.port());
  auto refused = test::split_responses(third.read_all(5));
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_EQ(refused[0].status, 503);
  EXPECT_NE(refused[0].head.find("Retry-After: 1"), std::string::npos) << refused[0].head;
  EXPECT_NE(refused[0].body.find("at most 2 connections"), std::string::npos);
  first.reset();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(server.client().get("/healthz").status, 200);
}

// A data directory on a file system of a few MiB (tmpfs, mounted for the test; the suite
// runs as root), to be filled on purpose.
class SmallDisk {
 public:
  explicit SmallDisk(const std::string& name) : dir_(test::fresh_temp_dir(name)) {
    auto mounted = test::run_command("mount -t tmpfs -o size=4m tmpfs " + dir_.string());
    if (mounted.exit_code != 0)
      throw std::runtime_error("cannot mount a tmpfs (the suite must run as root): " +
                               mounted.output);
  }
  ~SmallDisk() { test::run_command("umount -l " + dir_.string()); }
  const std::filesystem::path& dir() const { return dir_; }
  // Writes until the disk refuses.
  void fill() {
    std::ofstream out(dir_ / "filler", std::ios::binary);
    const std::string chunk(64 * 1024, 'x');
    while (out.write(chunk.data(), std::streamsize(chunk.size())) && out.flush()) {
    }
  }
  void make_room() { std::filesystem::remove(dir_ / "filler"); }

 private:
  std::filesystem::path dir_;
};

// Before: a submit on a full disk answered 500 with the server's absolute path, and its
// partial files stayed.
TEST(HostileInput, AFullDiskAnswers507AndLeavesNoPartialJob) {
  SmallDisk disk("hostile-disk");
  ServerProcess server(disk.dir());
  HttpClient c = server.client();
  disk.fill();
  HttpResponse r = c.request("POST", "/v1/jobs", test::small_job_json(5, 5));
  expect_problem(r, 507, "the server's disk is full");
  EXPECT_EQ(r.header("retry-after"), "60");
  EXPECT_EQ(r.body.find(disk.dir().string()), std::string::npos) << r.body;
  EXPECT_TRUE(std::filesystem::is_empty(disk.dir() / "jobs"));
  disk.make_room();
  std::string id = submit(c, test::small_job_json(5, 5));
  EXPECT_EQ(json::parse(test::wait_for_job(c, id, {"done", "failed"}))["state"], "done");
}

// Before: after a kill -9 the server would not start on a full disk, since it could not
// rewrite the record of the job that had been running.
TEST(HostileInput, AServerKilledOnAFullDiskStartsAgain) {
  SmallDisk disk("hostile-disk");
  std::string id;
  {
    ServerProcess server(disk.dir());
    HttpClient c = server.client();
    id = submit(c, test::small_job_json(0, 50, true));
    test::wait_for_job(c, id, {"running"});
    server.kill_hard();
  }
  disk.fill();
  ServerProcess again(disk.dir());
  json job = json::parse(again.client().get("/v1/jobs/" + id).body);
  EXPECT_EQ(job["state"], "interrupted");
  EXPECT_NE(again.log().find("the server's disk is full"), std::string::npos) << again.log();
}

}  // namespace
}  // namespace bumprad
