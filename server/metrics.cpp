#include "server/metrics.h"

#include <sstream>

namespace bumprad {
namespace {

constexpr std::array<double, 8> kBounds = {0.001, 0.005, 0.02, 0.05, 0.1, 0.5, 2, 10};

}  // namespace

void Metrics::count_request(std::string_view method, std::string_view route, int status,
                            double seconds) {
  std::lock_guard lock(mutex_);
  ++requests_[{std::string(method), std::string(route), status}];
  Latency& l = latency_[{std::string(method), std::string(route)}];
  ++l.count;
  l.sum += seconds;
  for (std::size_t i = 0; i < kBounds.size(); ++i)
    if (seconds <= kBounds[i]) ++l.buckets[i];
}

void Metrics::count_shots(int shots, double seconds) {
  std::lock_guard lock(mutex_);
  shots_ += std::uint64_t(shots);
  shot_seconds_ += seconds;
}

void Metrics::count_claim() {
  std::lock_guard lock(mutex_);
  ++claims_;
}

void Metrics::count_lease_renewal() {
  std::lock_guard lock(mutex_);
  ++lease_renewals_;
}

std::string Metrics::prometheus(const Gauges& g) const {
  std::lock_guard lock(mutex_);
  std::ostringstream out;
  out << "# HELP bumprad_store_up Whether the job store answers.\n# TYPE bumprad_store_up gauge\n"
      << "bumprad_store_up " << (g.store_up ? 1 : 0) << "\n";
  out << "# HELP bumprad_jobs Jobs in the store, by state.\n# TYPE bumprad_jobs gauge\n";
  for (std::size_t i = 0; i < g.jobs_by_state.size(); ++i)
    out << "bumprad_jobs{state=\"" << to_string(JobState(i)) << "\"} " << g.jobs_by_state[i]
        << "\n";
  out << "# HELP bumprad_queue_depth Jobs waiting for a worker.\n# TYPE bumprad_queue_depth "
         "gauge\nbumprad_queue_depth "
      << g.jobs_by_state[std::size_t(JobState::Queued)]
      << "\n# HELP bumprad_queue_capacity Most jobs that may wait.\n"
      << "# TYPE bumprad_queue_capacity gauge\nbumprad_queue_capacity " << g.queue_capacity
      << "\n# HELP bumprad_workers Solver threads in this process.\n# TYPE bumprad_workers gauge\n"
      << "bumprad_workers " << g.workers << "\n";
  out << "# HELP bumprad_claims_total Jobs this process's workers claimed.\n"
      << "# TYPE bumprad_claims_total counter\nbumprad_claims_total " << claims_ << "\n"
      << "# HELP bumprad_lease_renewals_total Leases renewed at refinement steps.\n"
      << "# TYPE bumprad_lease_renewals_total counter\nbumprad_lease_renewals_total "
      << lease_renewals_ << "\n";
  out << "# HELP bumprad_shots_total Shots solved (rate() gives shots per second).\n"
      << "# TYPE bumprad_shots_total counter\nbumprad_shots_total " << shots_ << "\n"
      << "# HELP bumprad_shot_seconds_total Solver time spent on those shots.\n"
      << "# TYPE bumprad_shot_seconds_total counter\nbumprad_shot_seconds_total " << shot_seconds_
      << "\n";
  out << "# HELP bumprad_http_requests_total Requests answered, by route and status.\n"
      << "# TYPE bumprad_http_requests_total counter\n";
  for (const auto& [key, n] : requests_)
    out << "bumprad_http_requests_total{method=\"" << std::get<0>(key) << "\",route=\""
        << std::get<1>(key) << "\",status=\"" << std::get<2>(key) << "\"} " << n << "\n";
  out << "# HELP bumprad_http_request_seconds Time to answer, by route (streams: to the end).\n"
      << "# TYPE bumprad_http_request_seconds histogram\n";
  for (const auto& [key, l] : latency_) {
    std::string labels = "method=\"" + key.first + "\",route=\"" + key.second + "\"";
    for (std::size_t i = 0; i < kBounds.size(); ++i)
      out << "bumprad_http_request_seconds_bucket{" << labels << ",le=\"" << kBounds[i] << "\"} "
          << l.buckets[i] << "\n";
    out << "bumprad_http_request_seconds_bucket{" << labels << ",le=\"+Inf\"} " << l.count
        << "\nbumprad_http_request_seconds_sum{" << labels << "} " << l.sum
        << "\nbumprad_http_request_seconds_count{" << labels << "} " << l.count << "\n";
  }
  return out.str();
}

}  // namespace bumprad
