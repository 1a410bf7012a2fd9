// The HTTP API's routes (protocol/openapi.json): each request becomes an answer to write
// now, a stream of a job's steps to keep writing, or a re-texture to render off the network
// threads. It knows no sockets; the session (http_session.h) does the I/O.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <stop_token>
#include <string>
#include <variant>
#include <vector>

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

// One route of the API: its path pattern ("{name}" stands for one path segment, or its
// start before a literal suffix, as in "{n}.png") and the methods it answers (GET also
// answers HEAD). The pattern names the route in metrics and logs.
struct RouteSpec {
  std::string_view pattern;
  std::vector<http::verb> methods;
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

  // Every route the API answers, the web viewer's files included (from the route table,
  // which also gives the Allow headers and 405s).
  static std::vector<RouteSpec> routes();

 private:
  // A request matched to a route: the values of the pattern's {name} segments.
  struct Call {
    const Request& request;
    std::string_view pattern;
    std::vector<std::pair<std::string_view, std::string_view>> params;
    std::string_view query;
    std::string_view param(std::string_view name) const;
  };
  using Handler = Routed (Api::*)(const Call&);
  using JobHandler = Routed (Api::*)(const Call&, const JobRecord&);
  struct Route {
    std::string_view pattern;
    http::verb method;
    std::variant<Handler, JobHandler> handler;
  };
  static std::span<const Route> route_table();

  Routed route(const Request& request);
  Routed web_asset(const Call& call);
  Routed health(const Call& call);
  Routed metrics(const Call& call);
  Routed scenes(const Call& call);
  Routed scene(const Call& call);
  Routed jobs(const Call& call);
  Routed submit_job(const Call& call);
  Routed validate_job(const Call& call);
  // Finds the job the call's {id} names, then answers with `then`; 404 if there is none.
  Routed with_job(const Call& call, JobHandler then);
  Routed not_found(const Call& call) const;
  Routed job(const Call& call, const JobRecord& record);
  Routed delete_job(const Call& call, const JobRecord& record);
  Routed retexture_job(const Call& call, const JobRecord& record);
  Routed job_events(const Call& call, const JobRecord& record);
  Routed job_step(const Call& call, const JobRecord& record);
  Routed job_preview(const Call& call, const JobRecord& record);
  Routed job_scene(const Call& call, const JobRecord& record);
  Routed job_solution(const Call& call, const JobRecord& record);
  Routed job_model(const Call& call, const JobRecord& record);
  Routed job_image(const Call& call, const JobRecord& record);
  // A step's PNG, or why there is none.
  Routed step_answer(const Call& call, const JobRecord& record, int step, bool immutable);
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
