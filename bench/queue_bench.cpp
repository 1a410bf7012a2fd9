// Queue benchmark: how fast one PostgreSQL hands out jobs, and how jobs per minute grow with
// worker processes.
//   build/bin/bumprad-bench-queue [--store postgresql://...] [--jobs N] [--claimers 1,4,16]
//                                 [--workers 1,2,4] [--farm-jobs M]
// Without --store it starts a throw-away cluster (Debian's postgresql, as the tests do; its
// default settings, fsync on). Three measurements:
//  - dispatch: N queued jobs; K threads, each a worker node with its own connections, claim a
//    job, renew its lease once and finish it with small results (12 KB), until none is left:
//    claim cycles per second and each call's median and p99 latency; then N/10 jobs with the
//    Cornell box's results (0.7 MB: image, EXR, solution with its map) on 4 threads.
//  - renewals: K threads each renew the lease of a job they hold, as a solving worker does
//    at every refinement step: renewals per second.
//  - farm: W `bumprad worker` processes and one API node; M small jobs posted over HTTP,
//    time until all are done: jobs per minute.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/args.h"
#include "common/stopwatch.h"
#include "server/postgres_store.h"
#include "tests/postgres_cluster.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(p * double(v.size())))];
}

// Where the databases come from: the URL given (every run shares it) or a throw-away cluster
// with a fresh database per run.
class Databases {
 public:
  explicit Databases(std::string url) : url_(std::move(url)) {
    if (url_.empty()) cluster_ = std::make_unique<test::PostgresCluster>();
  }
  std::string next() {
    return cluster_ ? cluster_->create_database("bench" + std::to_string(++n_)) : url_;
  }

 private:
  std::string url_;
  std::unique_ptr<test::PostgresCluster> cluster_;
  int n_ = 0;
};

StoreOptions roomy(std::size_t jobs) {
  StoreOptions o;
  o.max_queue = jobs + 1;
  o.retention.max_jobs = jobs + 1;  // nothing evicted while measuring
  return o;
}

JobRecord queued_record() {
  JobRecord r;
  r.id = new_job_id();
  r.created = unix_now();
  return r;
}

// Bytes that do not compress, as PNG and EXR do not.
std::string noise(std::size_t n) {
  std::string s(n, '\0');
  std::uint64_t x = 0x9e3779b97f4a7c15ull;
  for (char& c : s) {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    c = char(x);
  }
  return s;
}

void dispatch(const std::string& url, int jobs, int claimers, const Results& results) {
  PostgresStore submitter(url, roomy(std::size_t(jobs)));
  const std::string scene = test::small_scene_json(10);
  auto t = Clock::now();
  for (int i = 0; i < jobs; ++i) submitter.submit(queued_record(), scene, "");
  const double submit_s = seconds_since(t);

  std::vector<std::unique_ptr<PostgresStore>> nodes;
  for (int k = 0; k < claimers; ++k)
    nodes.push_back(std::make_unique<PostgresStore>(url, roomy(std::size_t(jobs))));
  using Times = std::vector<std::vector<double>>;  // per thread
  Times claim_s(nodes.size()), renew_s(nodes.size()), finish_s(nodes.size());
  std::atomic<long> done{0};  // this run's jobs (a shared --store may hold others)
  t = Clock::now();
  std::vector<std::thread> threads;
  for (int k = 0; k < claimers; ++k)
    threads.emplace_back([&, k] {
      const auto i = std::size_t(k);
      const std::string worker = "bench/" + std::to_string(k);
      for (;;) {
        auto c = Clock::now();
        std::optional<Claim> claim = nodes[i]->claim(worker);
        claim_s[i].push_back(seconds_since(c));
        if (!claim) return;
        c = Clock::now();
        nodes[i]->progress(worker, claim->record, "");
        renew_s[i].push_back(seconds_since(c));
        claim->record.state = JobState::Done;
        c = Clock::now();
        if (nodes[i]->finish(worker, claim->record, &results)) ++done;
        finish_s[i].push_back(seconds_since(c));
      }
    });
  for (auto& th : threads) th.join();
  const double cycle_s = seconds_since(t);
  auto all = [](const std::vector<std::vector<double>>& parts) {
    std::vector<double> v;
    for (const auto& p : parts) v.insert(v.end(), p.begin(), p.end());
    return v;
  };
  const double mb = double(results.png.size() + results.exr.size() + results.solution.size()) / 1e6;
  std::printf(
      "dispatch  claimers %2d: %5d jobs, %.2f MB results  submit %6.0f/s  "
      "claim+renew+finish %6.0f/s (%.0f MB/s)  "
      "ms p50/p99: claim %.2f/%.2f renew %.2f/%.2f finish %.2f/%.2f%s\n",
      claimers, jobs, mb, jobs / submit_s, double(done) / cycle_s, mb * double(done) / cycle_s,
      1e3 * percentile(all(claim_s), 0.5), 1e3 * percentile(all(claim_s), 0.99),
      1e3 * percentile(all(renew_s), 0.5), 1e3 * percentile(all(renew_s), 0.99),
      1e3 * percentile(all(finish_s), 0.5), 1e3 * percentile(all(finish_s), 0.99),
      done == jobs ? "" : "  (NOT ALL DONE)");
}

void renewals(const std::string& url, int holders, double seconds) {
  std::vector<std::unique_ptr<PostgresStore>> nodes;
  for (int k = 0; k < holders; ++k)
    nodes.push_back(std::make_unique<PostgresStore>(url, roomy(std::size_t(holders))));
  const std::string scene = test::small_scene_json(10);
  for (int k = 0; k < holders; ++k) nodes[0]->submit(queued_record(), scene, "");
  std::atomic<long> total{0};
  std::vector<std::thread> threads;
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  for (int k = 0; k < holders; ++k)
    threads.emplace_back([&, k] {
      const auto i = std::size_t(k);
      const std::string worker = "bench/" + std::to_string(k);
      std::optional<Claim> claim = nodes[i]->claim(worker);
      if (!claim) return;
      long n = 0;
      while (Clock::now() < end) {
        ++claim->record.shots;
        if (nodes[i]->progress(worker, claim->record, "") == Store::Lease::Held) ++n;
      }
      total += n;
      claim->record.state = JobState::Cancelled;  // nothing left running for the next run
      nodes[i]->finish(worker, claim->record, nullptr);
    });
  for (auto& th : threads) th.join();
  std::printf("renewals  holders  %2d: %6.0f lease renewals/s\n", holders, double(total) / seconds);
}

void farm(const std::string& url, int workers, int jobs) {
  char pattern[] = "/tmp/bumprad-queue-bench-XXXXXX";
  const std::filesystem::path dir = mkdtemp(pattern);
  const std::vector<std::string> store = {"--store", url, "--max-queue", std::to_string(jobs + 1)};
  test::ServerProcess api(dir / "api", store);
  std::vector<std::unique_ptr<test::ServerProcess>> nodes;
  for (int w = 0; w < workers; ++w)
    nodes.push_back(std::make_unique<test::ServerProcess>(
        dir / ("worker" + std::to_string(w)), store, std::vector<std::string>{}, "worker"));
  PostgresStore watch(url, roomy(std::size_t(jobs)));
  const auto done_before = watch.counts().jobs_by_state[std::size_t(JobState::Done)];
  const std::string body = test::small_job_json(40, 10);
  HttpClient client = api.client();
  auto t = Clock::now();
  for (int i = 0; i < jobs; ++i)
    if (HttpResponse r = client.request("POST", "/v1/jobs", body); r.status != 202)
      throw std::runtime_error("submit: " + r.problem());
  std::size_t done = 0;
  while (done < std::size_t(jobs) && seconds_since(t) < 600) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    done = watch.counts().jobs_by_state[std::size_t(JobState::Done)] - done_before;
  }
  const double s = seconds_since(t);
  std::printf("farm      workers  %2d: %4zu jobs in %6.2f s  %7.1f jobs/min\n", workers, done, s,
              60.0 * double(done) / s);
  nodes.clear();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace bumprad

int main(int argc, char** argv) {
  using namespace bumprad;
  std::string url;
  int jobs = 2000, farm_jobs = 60;
  std::vector<int> claimers = {1, 4, 16}, workers = {1, 2, 4};
  const auto list = [](std::vector<int>& out) {
    return [&out](std::string_view flag, std::string_view text) {
      out.clear();
      for (std::size_t start = 0; start <= text.size();) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        out.push_back(int(parse_integer(flag, text.substr(start, comma - start), 1, 1'000'000)));
        start = comma + 1;
      }
    };
  };
  ArgParser()
      .text({"--store"}, url)
      .integer({"--jobs"}, jobs, 1, 100'000'000)
      .custom({"--claimers"}, list(claimers))
      .custom({"--workers"}, list(workers))
      .integer({"--farm-jobs"}, farm_jobs, 1, 100'000'000)
      .parse_or_exit(argc, argv, "options: see the comment at the top of bench/queue_bench.cpp\n");
  try {
    Databases databases(url);
    std::printf("bumprad-bench-queue: %u CPU threads\n", std::thread::hardware_concurrency());
    const Results small{noise(4096), noise(4096), noise(4096)};
    for (int k : claimers) dispatch(databases.next(), jobs, k, small);
    // The Cornell box's image, EXR and solution with its map, as a worker stores them.
    const Results cornell{noise(106'672), noise(425'074), noise(173'214)};
    dispatch(databases.next(), std::max(1, jobs / 10), 4, cornell);
    for (int k : claimers) renewals(databases.next(), k, 3);
    for (int w : workers) farm(databases.next(), w, farm_jobs);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bumprad-bench-queue: %s\n", e.what());
    return 1;
  }
}
