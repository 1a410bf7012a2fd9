// Counters for GET /metrics in Prometheus' text format: requests and their latencies by
// route and status, solver shots, claims and lease renewals, and the gauges the store
// reports when asked.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>

#include "protocol/api_json.h"

namespace bumprad {

class Metrics {
 public:
  // `route` is the route's pattern ("/v1/jobs/{id}"), so labels stay few.
  void count_request(std::string_view method, std::string_view route, int status, double seconds);
  void count_shots(int shots, double seconds);
  void count_claim();
  void count_lease_renewal();

  struct Gauges {
    std::array<std::size_t, 6> jobs_by_state{};  // indexed by JobState
    std::size_t queue_capacity = 0, workers = 0;
    bool store_up = true;
  };
  std::string prometheus(const Gauges& gauges) const;

 private:
  struct Latency {
    std::uint64_t count = 0;
    double sum = 0;
    std::array<std::uint64_t, 8> buckets{};  // cumulative: each counts those within its bound
  };
  mutable std::mutex mutex_;
  std::map<std::pair<std::string, std::string>, Latency> latency_;  // method, route
  std::map<std::tuple<std::string, std::string, int>, std::uint64_t> requests_;
  std::uint64_t shots_ = 0, claims_ = 0, lease_renewals_ = 0;
  double shot_seconds_ = 0;
};

}  // namespace bumprad
