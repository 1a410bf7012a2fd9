// The Prometheus text: requests counted by method, route and status, latencies in cumulative
// buckets, the workers' counters and the store's gauges.
#include "server/metrics.h"

#include <gtest/gtest.h>

namespace bumprad {
namespace {

bool has(const std::string& text, const std::string& line) {
  return text.find("\n" + line + "\n") != std::string::npos;
}

TEST(Metrics, CountsAndLatenciesByRouteAndStatus) {
  Metrics m;
  m.count_request("GET", "/v1/jobs", 200, 0.002);
  m.count_request("GET", "/v1/jobs", 200, 0.3);
  m.count_request("GET", "/v1/jobs", 503, 0.001);
  m.count_request("POST", "/v1/jobs/{id}/retexture", 200, 40);
  m.count_shots(30, 1.5);
  m.count_shots(10, 0.5);
  m.count_claim();
  m.count_lease_renewal();
  m.count_lease_renewal();
  Metrics::Gauges g;
  g.jobs_by_state[std::size_t(JobState::Queued)] = 3;
  g.queue_capacity = 16;
  g.workers = 2;
  const std::string text = m.prometheus(g);
  EXPECT_TRUE(
      has(text, R"(bumprad_http_requests_total{method="GET",route="/v1/jobs",status="200"} 2)"))
      << text;
  EXPECT_TRUE(
      has(text, R"(bumprad_http_requests_total{method="GET",route="/v1/jobs",status="503"} 1)"));
  EXPECT_TRUE(has(text, R"(bumprad_http_request_seconds_count{method="GET",route="/v1/jobs"} 3)"));
  EXPECT_TRUE(has(
      text, R"(bumprad_http_request_seconds_bucket{method="GET",route="/v1/jobs",le="+Inf"} 3)"));
  // 40 s is beyond every finite bucket of the re-texture route.
  EXPECT_EQ(text.find(R"(route="/v1/jobs/{id}/retexture",le="10"} 1)"), std::string::npos);
  EXPECT_TRUE(has(text, "bumprad_shots_total 40"));
  EXPECT_TRUE(has(text, "bumprad_shot_seconds_total 2"));
  EXPECT_TRUE(has(text, "bumprad_claims_total 1"));
  EXPECT_TRUE(has(text, "bumprad_lease_renewals_total 2"));
  EXPECT_TRUE(has(text, R"(bumprad_jobs{state="queued"} 3)"));
  EXPECT_TRUE(has(text, "bumprad_store_up 1"));
}

// Buckets are cumulative: each counts the requests within its bound.
TEST(Metrics, LatencyBucketsAreCumulative) {
  Metrics m;
  for (double s : {0.0001, 0.0001, 1000.0}) m.count_request("GET", "/healthz", 200, s);
  const std::string text = m.prometheus({});
  std::size_t at = 0;
  int last = 0, buckets = 0;
  const std::string prefix =
      R"(bumprad_http_request_seconds_bucket{method="GET",route="/healthz",le=")";
  while ((at = text.find(prefix, at)) != std::string::npos) {
    at = text.find("} ", at) + 2;
    const int n = std::stoi(text.substr(at));
    EXPECT_GE(n, last);
    last = n;
    ++buckets;
  }
  EXPECT_GT(buckets, 2);
  EXPECT_EQ(last, 3);  // +Inf
}

}  // namespace
}  // namespace bumprad
