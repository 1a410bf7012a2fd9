// The service's parts put together in the test process, without sockets: a node (store,
// workers, API) on a data directory. Requests go straight to Api::handle, and deferred work
// runs on the calling thread.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include "server/directory_store.h"
#include "server/node.h"

namespace bumprad::test {

inline NodeOptions node_options(const std::filesystem::path& dir) {
  NodeOptions options;
  options.data_dir = dir;
  return options;
}

inline Request request(http::verb method, std::string target, std::string body = {}) {
  Request r{method, target, 11};
  r.body() = std::move(body);
  r.prepare_payload();
  return r;
}

// Polls the job's record in `store` until its state is `state` or `seconds` pass.
inline JobRecord wait_for(Store& store, const std::string& id, JobState state,
                          double seconds = 30) {
  auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  for (;;) {
    auto r = store.find(id);
    if (!r) throw std::runtime_error("job " + id + " is gone");
    if (r->state == state) return *r;
    if (std::chrono::steady_clock::now() > deadline)
      throw std::runtime_error("job " + id + " is " + std::string(to_string(r->state)) + ": " +
                               r->error);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

struct InProcessServer {
  explicit InProcessServer(const std::filesystem::path& dir) : InProcessServer(node_options(dir)) {}
  explicit InProcessServer(const NodeOptions& options)
      : node(options), store(dynamic_cast<DirectoryStore&>(*node.store)), api(node.api) {}

  // The answer to `request`, running deferred work here with `stop`.
  Response answer(const Request& request, std::stop_source stop = {}) {
    Routed routed = api.handle(request);
    if (auto* r = std::get_if<Response>(&routed.action)) return *r;
    if (auto* d = std::get_if<DeferredRequest>(&routed.action)) return d->work(request, stop);
    throw std::logic_error("a stream, not an answer");
  }

  // POST /v1/jobs with `body`; the new job's id.
  std::string submit(const std::string& body) {
    Response res = answer(request(http::verb::post, "/v1/jobs", body));
    if (res.result() != http::status::accepted)
      throw std::runtime_error("submit answered " + std::to_string(res.result_int()) + ": " +
                               res.body());
    return job_from_json(res.body()).id;
  }

  JobRecord wait_for(const std::string& id, JobState state, double seconds = 30) {
    return test::wait_for(store, id, state, seconds);
  }

  Node node;
  DirectoryStore& store;
  Api& api;
};

}  // namespace bumprad::test
