// Service benchmark: what a user of a running `bumprad serve` waits for.
//   build/bin/bumprad-bench-service [--server http://HOST:PORT] [SCENE] [--retextures N]
// Submits builtin SCENE (default wrinkled-box), then reports the submit's answer time, the
// time to the first streamed step and to done, the server's own solve and preview times,
// and N re-textures of the solved job with alternating bump functions (median and p95),
// each a whole HTTP round trip with a 512 x 512 PNG answer, then N drafts (JPEG, one ray a
// pixel) one after another as a dragged slider sends them, in frames a second.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clients/event_stream.h"
#include "clients/http_client.h"
#include "common/args.h"
#include "common/stopwatch.h"

int main(int argc, char** argv) {
  using namespace bumprad;
  using json = nlohmann::json;
  std::string server = "http://127.0.0.1:8080", scene = "wrinkled-box";
  int retextures = 20;
  std::vector<std::string> positional;
  ArgParser()
      .text({"--server"}, server)
      .integer({"--retextures"}, retextures, 1, 100'000)
      .positional(positional, 1)
      .parse_or_exit(argc, argv,
                     "usage: bumprad-bench-service [SCENE] [--server URL] [--retextures N]\n");
  if (!positional.empty())
    scene = positional[0].starts_with("builtin:") ? positional[0].substr(8) : positional[0];
  try {
    auto [host, port] = parse_server_url(server);
    HttpClient client(host, port, 600);
    auto t0 = Clock::now();
    HttpResponse submitted = client.request("POST", "/v1/jobs", json{{"builtin", scene}}.dump());
    double submit_s = seconds_since(t0);
    if (submitted.status != 202) throw std::runtime_error(submitted.problem());
    std::string id = json::parse(submitted.body)["id"];

    double first_step_s = 0, done_s = 0;
    std::string end;
    EventStreamParser parser;
    client.stream("/v1/jobs/" + id + "/events", [&](std::string_view bytes) {
      for (const ServerEvent& e : parser.feed(bytes)) {
        if (e.name == "step" && first_step_s == 0) first_step_s = seconds_since(t0);
        if (e.name != "step" && e.name != "state") end = e.name;
      }
      return end.empty();
    });
    done_s = seconds_since(t0);
    json job = json::parse(client.get("/v1/jobs/" + id).body);
    if (end != "done") throw std::runtime_error("the job ended " + end);

    json bumps = json::parse(client.get("/v1/jobs/" + id + "/scene").body)["bumps"];
    // Each re-texture a whole HTTP round trip, one after another as a viewer sends them:
    // full quality (the camera's antialiasing, PNG), then drafts (one ray a pixel, JPEG) as
    // a dragged slider sends them.
    auto retexture_times = [&](const json& extra) {
      std::vector<double> times;
      for (int i = 0; i < retextures && !bumps.empty(); ++i) {
        json request = {{"bumps",
                         {{bumps.begin().key(),
                           {{"type", i % 2 ? "bricks" : "dimples"},
                            {"amplitude", 0.01 + 0.001 * i},
                            {"scale", 4 + i % 3}}}}}};
        request.update(extra);
        auto t = Clock::now();
        HttpResponse r = client.request("POST", "/v1/jobs/" + id + "/retexture", request.dump());
        times.push_back(seconds_since(t));
        if (r.status != 200) throw std::runtime_error(r.problem());
      }
      std::sort(times.begin(), times.end());
      return times;
    };
    const std::vector<double> finals = retexture_times(json::object());
    const std::vector<double> drafts = retexture_times({{"quality", "draft"}, {"format", "jpeg"}});
    auto at = [](const std::vector<double>& times, double q) {
      return 1000 * times[std::size_t(q * double(times.size() - 1))];
    };
    double drafts_s = 0;
    for (double t : drafts) drafts_s += t;

    std::printf("%s on %s: %d shots, %d elements, %d steps\n", scene.c_str(), server.c_str(),
                job["shots"].get<int>(), job["elements"].get<int>(), job["step"].get<int>());
    std::printf("  submit answered      %8.1f ms\n", 1000 * submit_s);
    std::printf("  first step streamed  %8.1f ms\n", 1000 * first_step_s);
    std::printf("  done                 %8.3f s (server: solve %.3f s, previews %.3f s)\n", done_s,
                job["timings"]["solve_s"].get<double>(),
                job["timings"]["previews_s"].get<double>());
    if (finals.empty()) {
      std::printf("  re-texture           (the scene has no bump functions)\n");
    } else {
      std::printf("  re-texture x%d       median %.1f ms, p95 %.1f ms (HTTP round trip, PNG)\n",
                  retextures, at(finals, 0.5), at(finals, 0.95));
      std::printf("  draft re-texture x%d median %.1f ms, p95 %.1f ms: %.1f frames a second\n",
                  retextures, at(drafts, 0.5), at(drafts, 0.95), double(drafts.size()) / drafts_s);
    }
    client.request("DELETE", "/v1/jobs/" + id);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bumprad-bench-service: %s\n", e.what());
    return 1;
  }
}
