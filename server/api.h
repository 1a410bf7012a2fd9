// The HTTP API's routes (protocol/openapi.json): each request becomes an answer to write
// now, a stream of a job's steps to keep writing, or a re-texture to render off the network
// threads. It knows no sockets; the session (http_session.h) does the I/O.
#pragma once

#include <functional>
#include <memory>
#include <stop_token>
#include <string>
#include <variant>

#include <boost/beast/http.hpp>

#include "server/job.h"
#include "server/live_jobs.h"
#include "server/metrics.h"
#include "server/solution_cache.h"
#include "server/store.h"
#include "server/watchdog.h"
#include "solver/cost.h"

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

// Work too long for a network thread (parsing a body, rendering); its answer is written
// when it is done. Renders go to their own pool, whose queue is bounded. The stop source
// stops the work when the client hangs up or the server shuts down.
struct DeferredRequest {
  enum class Pool { Parse, Render };
  Pool pool;
  std::function<Response(const Request&, std::stop_source)> work;
};

struct Routed {
  std::string route;  // the route's pattern, for metrics and logs
  std::variant<Response, StreamRequest, DeferredRequest> action;
};

// What one request may cost: bodies, and the estimated and wall-clock seconds of work.
struct ApiLimits {
  ImageFiles files = ImageFiles::refused();  // image files scenes may name
  std::size_t body_limit = 8 << 20;
  double max_job_seconds = 600;       // estimated solve and final render (solver/cost.h)
  double max_retexture_seconds = 30;  // estimated render
  double retexture_timeout_s = 60;    // wall clock, then 503
};

class Api {
 public:
  // `workers`: solver threads in this process, for /metrics (0 on an API-only node).
  Api(Store& store, LiveJobs& live, SolutionCache& solutions, Metrics& metrics, Watchdog& watchdog,
      ApiLimits limits, std::size_t workers)
      : store_(store),
        live_(live),
        solutions_(solutions),
        metrics_(metrics),
        watchdog_(watchdog),
        limits_(std::move(limits)),
        workers_(workers) {}

  // Never throws: every failure is a problem+json answer.
  Routed handle(const Request& request);

  const ApiLimits& limits() const { return limits_; }

 private:
  Routed route(const Request& request);
  // A job request parsed, validated and within the cost limit; throws SceneError.
  struct Accepted {
    JobRequest job;
    CostEstimate cost;
  };
  Accepted accept(const Request& request) const;
  Response validate(const Request& request);
  Response submit(const Request& request);
  Response retexture(const Request& request, const std::string& id, std::stop_source stop);
  Store& store_;
  LiveJobs& live_;
  SolutionCache& solutions_;
  Metrics& metrics_;
  Watchdog& watchdog_;
  const ApiLimits limits_;
  const std::size_t workers_;
};

// An RFC 9457 problem+json answer.
Response problem(const Request& request, http::status status, std::string_view title,
                 std::string_view detail, std::string_view field = {});

}  // namespace bumprad
