// Load benchmark for a running `bumprad serve`: many clients at once, each doing one kind
// of request over and over for a fixed time, and the latency every kind saw.
//   build/bin/bumprad-bench-load [--server http://HOST:PORT] [--seconds 20] [--clients 16]
// Clients, split evenly by kind: submit (a small inline job with 20 shots), events (follows
// one job's SSE stream to its end), retexture (a small re-texture of a solved job), health
// (GET /healthz) and big-body (an 8 MB scene that is refused after parsing: the network
// threads must stay free meanwhile). Reports count, errors (transport failures and 5xx;
// 429 and 503 with Retry-After are counted apart as refusals) and p50/p99 latency per kind.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "clients/event_stream.h"
#include "clients/http_client.h"
#include "common/args.h"
#include "common/stopwatch.h"

namespace {

using namespace bumprad;
using json = nlohmann::json;

const char* kSmallScene = R"({
  "camera": {"position": [0.6, 1.5, 1.9], "look_at": [0, 0.9, 0], "width": 64, "height": 48},
  "materials": {"wall": {"reflectance": 0.6}, "light": {"emission": 30}},
  "bumps": {"w": {"type": "wrinkles", "amplitude": 0.01, "scale": 6}},
  "objects": [
    {"type": "box", "material": "wall", "flip_normals": true, "center": [0, 1.5, 0],
     "size": [4, 3, 4], "bump": "w"},
    {"type": "quad", "material": "light", "vertices": [[-0.4, 2.99, -0.4], [0.4, 2.99, -0.4],
                                                       [0.4, 2.99, 0.4], [-0.4, 2.99, 0.4]]}],
  "solver": {"element_size": 0.5, "hemicube_resolution": 48, "max_shots": 20}})";

struct Tally {
  std::vector<double> seconds;
  int errors = 0, refused = 0;
};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(p * double(v.size())))];
}

}  // namespace

int main(int argc, char** argv) {
  std::string server = "http://127.0.0.1:8080";
  double seconds = 20;
  int clients = 16;
  ArgParser()
      .text({"--server"}, server)
      .number({"--seconds"}, seconds, 0.1, 86'400)
      .integer({"--clients"}, clients, 5, 10'000)
      .parse_or_exit(argc, argv,
                     "usage: bumprad-bench-load [--server URL] [--seconds S] [--clients N]\n");
  try {
    auto [host, port] = parse_server_url(server);
    const HttpClient setup(host, port, 600);
    const std::string job = json{{"scene", json::parse(kSmallScene)}}.dump();
    HttpResponse first = setup.request("POST", "/v1/jobs", job);
    if (first.status != 202) throw std::runtime_error(first.problem());
    const std::string solved = json::parse(first.body)["id"];
    while (json::parse(setup.get("/v1/jobs/" + solved).body)["state"] != "done")
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::string big = json{{"scene", {{"description", std::string(8'000'000, 'x')}}}}.dump();

    const std::vector<std::string> kinds = {"submit", "events", "retexture", "health", "big-body"};
    std::map<std::string, Tally> tallies;
    std::mutex mutex;
    const auto start = Clock::now();
    std::vector<std::thread> threads;
    for (int c = 0; c < clients; ++c)
      threads.emplace_back([&, kind = kinds[std::size_t(c) % kinds.size()]] {
        const HttpClient client(host, port, 120);
        while (seconds_since(start) < seconds) {
          auto t = Clock::now();
          int status = 0;
          try {
            if (kind == "submit") {
              status = client.request("POST", "/v1/jobs", job).status;
            } else if (kind == "events") {
              HttpResponse s = client.request("POST", "/v1/jobs", job);
              status = s.status;
              if (status == 202)
                status = client
                             .stream("/v1/jobs/" + json::parse(s.body)["id"].get<std::string>() +
                                         "/events",
                                     [&](std::string_view b) {
                                       return b.find("event: done") == std::string_view::npos;
                                     })
                             .status;
            } else if (kind == "retexture") {
              status = client
                           .request("POST", "/v1/jobs/" + solved + "/retexture",
                                    R"({"bumps": {"w": {"type": "dimples"}}})")
                           .status;
            } else if (kind == "health") {
              status = client.get("/healthz").status;
            } else {
              status = client.request("POST", "/v1/jobs", big).status;
            }
          } catch (const std::exception&) {
            status = -1;
          }
          const double s = seconds_since(t);
          std::lock_guard lock(mutex);
          Tally& tally = tallies[kind];
          tally.seconds.push_back(s);
          if (status == 429 || status == 503)
            ++tally.refused;
          else if (status < 0 || status >= 500)
            ++tally.errors;
          if (status == 429 || status == 503)  // back off as Retry-After asks, shortened
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
        }
      });
    for (auto& t : threads) t.join();
    std::printf("%d clients for %.0f s against %s\n", clients, seconds, server.c_str());
    std::printf("%-10s %8s %7s %8s %10s %10s\n", "kind", "requests", "errors", "refused", "p50 ms",
                "p99 ms");
    for (const std::string& kind : kinds) {
      const Tally& t = tallies[kind];
      std::printf("%-10s %8zu %7d %8d %10.1f %10.1f\n", kind.c_str(), t.seconds.size(), t.errors,
                  t.refused, 1000 * percentile(t.seconds, 0.5), 1000 * percentile(t.seconds, 0.99));
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bumprad-bench-load: %s\n", e.what());
    return 1;
  }
}
