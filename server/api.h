// The HTTP API's routes (protocol/openapi.json): each request becomes an answer to write
// now, a stream of a job's steps to keep writing, or a re-texture to render off the network
// threads. It knows no sockets; the session (http_session.h) does the I/O.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <variant>

#include <boost/beast/http.hpp>

#include "server/job_queue.h"
#include "server/metrics.h"

namespace bumprad {

namespace http = boost::beast::http;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;

// A job's refinement steps as Server-Sent Events, or as a multipart/x-mixed-replace stream
// of PNGs that a plain <img> shows.
struct StreamRequest {
  enum class Kind { Events, Images };
  std::shared_ptr<Job> job;
  Kind kind;
};

// Work too long for a network thread; its answer is written when it is done.
struct DeferredRequest {
  std::function<Response()> work;
};

struct Routed {
  std::string route;  // the route's pattern, for metrics and logs
  std::variant<Response, StreamRequest, DeferredRequest> action;
};

class Api {
 public:
  Api(JobQueue& queue, Metrics& metrics, std::size_t body_limit)
      : queue_(queue), metrics_(metrics), body_limit_(body_limit) {}

  // Never throws: every failure is a problem+json answer.
  Routed handle(const Request& request);

  std::size_t body_limit() const { return body_limit_; }

 private:
  Routed route(const Request& request);
  JobQueue& queue_;
  Metrics& metrics_;
  std::size_t body_limit_;
};

// An RFC 9457 problem+json answer.
Response problem(const Request& request, http::status status, std::string_view title,
                 std::string_view detail, std::string_view field = {});

}  // namespace bumprad
