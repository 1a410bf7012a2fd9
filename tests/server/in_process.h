// The service's parts put together in the test process, without sockets: a data directory,
// the queue with its worker, the API. Requests go straight to Api::handle, and deferred
// work runs on the calling thread.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include "server/api.h"
#include "server/job_queue.h"
#include "server/job_store.h"
#include "server/watchdog.h"

namespace bumprad::test {

struct InProcessServer {
  explicit InProcessServer(const std::filesystem::path& dir, QueueOptions options = {},
                           ApiLimits limits = {})
      : store(dir),
        queue(store, metrics, watchdog, std::move(options)),
        api(queue, metrics, watchdog, limits) {}

  // The answer to `request`, running deferred work here with `stop`.
  Response answer(const Request& request, std::stop_source stop = {}) {
    Routed routed = api.handle(request);
    if (auto* r = std::get_if<Response>(&routed.action)) return *r;
    if (auto* d = std::get_if<DeferredRequest>(&routed.action)) return d->work(request, stop);
    throw std::logic_error("a stream, not an answer");
  }

  // Polls the job's record until its state is `state` or `seconds` pass.
  JobRecord wait_for(const std::string& id, JobState state, double seconds = 30) {
    auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    for (;;) {
      auto job = queue.find(id);
      if (!job) throw std::runtime_error("job " + id + " is gone");
      JobRecord r = job->record();
      if (r.state == state) return r;
      if (std::chrono::steady_clock::now() > deadline)
        throw std::runtime_error("job " + id + " is " + std::string(to_string(r.state)));
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  Metrics metrics;
  Watchdog watchdog;
  JobStore store;
  JobQueue queue;
  Api api;
};

inline Request request(http::verb method, std::string target, std::string body = {}) {
  Request r{method, target, 11};
  r.body() = std::move(body);
  r.prepare_payload();
  return r;
}

}  // namespace bumprad::test
