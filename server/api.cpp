#include "server/api.h"

#include <charconv>
#include <cstdio>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/stopwatch.h"
#include "protocol/api_json.h"
#include "protocol/builtin_scenes.h"
#include "protocol/gltf_export.h"
#include "protocol/upload.h"
#include "server/step_stream.h"
#include "server/web_assets.h"
#include "solver/cost.h"
#include "solver/solution.h"

namespace bumprad {
namespace {

constexpr std::string_view kIdempotencyKey = "Idempotency-Key";
constexpr std::string_view kKeyCharacters =
    " !\"#$%&'()*+,-./"
    "0123456789:;<=>?@ABCDEFGHIJKLMNOPQRSTUVWXYZ[\\]^_`abcdefghijklmnopqrstuvwxyz{|}~";

std::vector<std::string_view> split_path(std::string_view path) {
  std::vector<std::string_view> parts;
  while (!path.empty()) {
    auto slash = path.find('/');
    if (slash != 0) parts.push_back(path.substr(0, slash));
    if (slash == std::string_view::npos) break;
    path.remove_prefix(slash + 1);
  }
  return parts;
}

// The value of `key` in a query string ("format=png&x=1"); our values need no decoding.
std::optional<std::string_view> query_value(std::string_view query, std::string_view key) {
  while (!query.empty()) {
    auto amp = query.find('&');
    std::string_view pair = query.substr(0, amp);
    if (pair.substr(0, pair.find('=')) == key)
      return pair.find('=') == std::string_view::npos ? "" : pair.substr(pair.find('=') + 1);
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
  return std::nullopt;
}

std::optional<int> to_int(std::string_view s) {
  int v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

Response answer(const Request& request, http::status status, std::string_view content_type,
                std::string body) {
  Response res{status, request.version()};
  res.set(http::field::server, "bumprad");
  res.set(http::field::content_type, content_type);
  res.keep_alive(request.keep_alive());
  res.body() = std::move(body);
  res.prepare_payload();
  return res;
}

Response json_answer(const Request& request, http::status status, std::string body) {
  return answer(request, status, "application/json", std::move(body));
}

Response png_answer(const Request& request, std::string png, int step, bool immutable) {
  Response res = answer(request, http::status::ok, "image/png", std::move(png));
  res.set("X-Bumprad-Step", std::to_string(step));
  res.set(http::field::cache_control,
          immutable ? "public, max-age=31536000, immutable" : "no-cache");
  return res;
}

// 405 with the Allow header that lists what the route answers.
Response method_not_allowed(const Request& request, const std::vector<http::verb>& methods) {
  std::string allowed;
  for (http::verb v : methods) {
    if (!allowed.empty()) allowed += ", ";
    allowed += std::string(http::to_string(v));
    if (v == http::verb::get) allowed += ", HEAD";
  }
  Response res =
      problem(request, http::status::method_not_allowed, "Method not allowed",
              std::string(request.method_string()) + " is not allowed here; use " + allowed);
  res.set(http::field::allow, allowed);
  return res;
}

Response scene_problem(const Request& request, const SceneError& e) {
  bool malformed = dynamic_cast<const MalformedJson*>(&e) != nullptr;
  return problem(
      request, malformed ? http::status::bad_request : http::status::unprocessable_entity,
      malformed ? "Malformed JSON" : "Invalid request", malformed ? e.reason() : e.what(),
      malformed ? std::string_view{} : std::string_view(e.pointer().empty() ? "/" : e.pointer()));
}

// "40 ms", "12 s", "3.5 min", "11 h": for cost and time-limit messages.
std::string describe_duration(double seconds) {
  char s[32];
  if (seconds < 1)
    std::snprintf(s, sizeof s, "%.0f ms", seconds * 1000);
  else if (seconds < 120)
    std::snprintf(s, sizeof s, "%.3g s", seconds);
  else if (seconds < 7200)
    std::snprintf(s, sizeof s, "%.3g min", seconds / 60);
  else
    std::snprintf(s, sizeof s, "%.3g h", seconds / 3600);
  return s;
}

}  // namespace

Response problem(const Request& request, http::status status, std::string_view title,
                 std::string_view detail, std::string_view field) {
  return answer(request, status, "application/problem+json",
                problem_json(int(status), title, detail, field));
}

namespace {

// A 500 says nothing of the server's inside (paths, library messages); its log does.
Response internal_error(const Request& request, std::string_view what) {
  std::fprintf(stderr, "internal error answering %s %s: %s\n",
               std::string(request.method_string()).c_str(), valid_utf8(request.target()).c_str(),
               valid_utf8(what).c_str());
  return problem(request, http::status::internal_server_error, "Internal error",
                 "the server could not answer this request; its log says why");
}

// The answer to a request a handler refused by throwing `e`: the exceptions of parsing a job,
// storing it, and anything else as an internal error.
Response refusal(const Request& request, std::exception_ptr thrown) {
  try {
    std::rethrow_exception(thrown);
  } catch (const SceneError& e) {
    return scene_problem(request, e);
  } catch (const UnsupportedMediaType& e) {
    return problem(request, http::status::unsupported_media_type, "Unsupported media type",
                   e.what());
  } catch (const MalformedBody& e) {
    return problem(request, http::status::bad_request, "Malformed body", e.what());
  } catch (const KeyReused& e) {
    return problem(request, http::status::unprocessable_entity, "Idempotency-Key reused", e.what(),
                   kIdempotencyKey);
  } catch (const QueueFull& e) {
    Response res = problem(request, http::status::too_many_requests, "Queue full", e.what());
    res.set(http::field::retry_after, "5");
    return res;
  } catch (const StoreFull& e) {
    Response res = problem(request, http::status::insufficient_storage, "Storage full", e.what());
    res.set(http::field::retry_after, "60");
    return res;
  } catch (const StoreUnavailable& e) {
    // The cause goes to the log; the client hears that it may retry.
    std::fprintf(stderr, "store unavailable answering %s: %s\n",
                 valid_utf8(request.target()).c_str(), e.what());
    Response res = problem(request, http::status::service_unavailable, "Store unavailable",
                           "the job store does not answer; retry after Retry-After seconds");
    res.set(http::field::retry_after, "5");
    return res;
  } catch (const std::exception& e) {
    return internal_error(request, e.what());
  }
}

}  // namespace

Routed Api::handle(const Request& request) {
  Routed routed;
  try {
    routed = route(request);
  } catch (...) {
    routed = {"(error)", refusal(request, std::current_exception())};
  }
  if (request.method() != http::verb::head) return routed;
  // HEAD: what GET would answer, without its body.
  if (auto* stream = std::get_if<StreamRequest>(&routed.action)) {
    Response res = answer(request, http::status::ok, StepStream(stream->kind).content_type(), "");
    res.erase(http::field::content_length);  // a stream's length is not known
    res.keep_alive(false);
    routed.action = std::move(res);
  }
  if (auto* res = std::get_if<Response>(&routed.action)) {
    const std::size_t length = res->body().size();
    res->body().clear();
    res->content_length(length);
  }
  return routed;
}

// The route table: one row per pattern and method. Web assets are served from their own
// literal paths, checked first (route()).
std::span<const Api::Route> Api::route_table() {
  using V = http::verb;
  static const Route kRoutes[] = {
      {"/healthz", V::get, &Api::health},
      {"/metrics", V::get, &Api::metrics},
      {"/v1/scenes", V::get, &Api::scenes},
      {"/v1/scenes/{name}", V::get, &Api::scene},
      {"/v1/validate", V::post, &Api::validate_job},
      {"/v1/jobs", V::get, &Api::jobs},
      {"/v1/jobs", V::post, &Api::submit_job},
      {"/v1/jobs/{id}", V::get, &Api::job},
      {"/v1/jobs/{id}", V::delete_, &Api::delete_job},
      {"/v1/jobs/{id}/retexture", V::post, &Api::retexture_job},
      {"/v1/jobs/{id}/stream", V::get, &Api::job_events},
      {"/v1/jobs/{id}/events", V::get, &Api::job_events},
      {"/v1/jobs/{id}/steps/{n}.png", V::get, &Api::job_step},
      {"/v1/jobs/{id}/preview", V::get, &Api::job_preview},
      {"/v1/jobs/{id}/scene", V::get, &Api::job_scene},
      {"/v1/jobs/{id}/solution", V::get, &Api::job_solution},
      {"/v1/jobs/{id}/model.glb", V::get, &Api::job_model},
      {"/v1/jobs/{id}/image", V::get, &Api::job_image},
  };
  return kRoutes;
}

namespace {

// Whether `path` fits `pattern`, segment by segment; the {name} segments' values go to
// `params`. A {name} may be followed by a literal suffix within its segment ("{n}.png").
bool match(std::string_view pattern, std::string_view path,
           std::vector<std::pair<std::string_view, std::string_view>>& params) {
  params.clear();
  const auto want = split_path(pattern), got = split_path(path);
  if (want.size() != got.size() || (path == "/") != (pattern == "/")) return false;
  for (std::size_t i = 0; i < want.size(); ++i) {
    const std::string_view w = want[i], g = got[i];
    if (!w.starts_with('{')) {
      if (w != g) return false;
      continue;
    }
    const std::size_t close = w.find('}');
    const std::string_view suffix = w.substr(close + 1);
    if (g.size() <= suffix.size() || !g.ends_with(suffix)) return false;
    params.emplace_back(w.substr(1, close - 1), g.substr(0, g.size() - suffix.size()));
  }
  return true;
}

}  // namespace

std::vector<RouteSpec> Api::routes() {
  std::vector<RouteSpec> out;
  for (const WebAsset& asset : web_assets()) out.push_back({asset.path, {http::verb::get}});
  for (const Route& r : route_table()) {
    if (out.empty() || out.back().pattern != r.pattern) out.push_back({r.pattern, {}});
    out.back().methods.push_back(r.method);
  }
  return out;
}

std::string_view Api::Call::param(std::string_view name) const {
  for (const auto& [key, value] : params)
    if (key == name) return value;
  return {};
}

Routed Api::route(const Request& request) {
  std::string_view target = request.target();
  std::string_view path = target.substr(0, target.find('?'));
  Call call{request, {}, {}, ""};
  if (target.find('?') != std::string_view::npos) call.query = target.substr(target.find('?') + 1);
  // HEAD is answered as GET; handle() drops the body.
  const http::verb method =
      request.method() == http::verb::head ? http::verb::get : request.method();
  std::vector<http::verb> allowed;
  for (const WebAsset& asset : web_assets())
    if (asset.path == path) {
      call.pattern = asset.path;
      if (method == http::verb::get) return web_asset(call);
      allowed = {http::verb::get};
    }
  for (const Route& r : allowed.empty() ? route_table() : std::span<const Route>{}) {
    if (!match(r.pattern, path, call.params)) continue;
    call.pattern = r.pattern;
    if (r.method != method) {
      allowed.push_back(r.method);
      continue;
    }
    if (auto* plain = std::get_if<Handler>(&r.handler)) return (this->*(*plain))(call);
    return with_job(call, std::get<JobHandler>(r.handler));
  }
  if (allowed.empty())
    return {"(unknown)", problem(request, http::status::not_found, "Not found",
                                 "no such resource: " + std::string(path))};
  return {std::string(call.pattern), method_not_allowed(request, allowed)};
}

Routed Api::web_asset(const Call& call) {
  for (const WebAsset& asset : web_assets())
    if (asset.path == call.pattern) {
      std::string type(asset.content_type);
      if (type.starts_with("text/")) type += "; charset=utf-8";
      return {std::string(asset.path),
              answer(call.request, http::status::ok, type, std::string(asset.body))};
    }
  return {"(unknown)", problem(call.request, http::status::not_found, "Not found", "no such file")};
}

Routed Api::health(const Call& call) {
  // The store's own words name its host, port or socket: they go to the log only.
  if (auto trouble = store_.health()) {
    std::fprintf(stderr, "healthz: the store does not answer: %s\n", valid_utf8(*trouble).c_str());
    Response res = json_answer(call.request, http::status::service_unavailable,
                               R"({"status":"unavailable","store":"unavailable"})");
    res.set(http::field::retry_after, "5");
    return {"/healthz", std::move(res)};
  }
  return {"/healthz",
          json_answer(call.request, http::status::ok, R"({"status":"ok","store":"ok"})")};
}

Routed Api::metrics(const Call& call) {
  Metrics::Gauges gauges;
  gauges.store_up = !store_.health();
  if (gauges.store_up) gauges.jobs_by_state = store_.counts().jobs_by_state;
  gauges.queue_capacity = store_.options().max_queue;
  gauges.workers = workers_;
  return {"/metrics", answer(call.request, http::status::ok, "text/plain; version=0.0.4",
                             metrics_.prometheus(gauges))};
}

Routed Api::scenes(const Call& call) {
  return {"/v1/scenes", json_answer(call.request, http::status::ok, builtin_scenes_json())};
}

Routed Api::scene(const Call& call) {
  const std::string_view name = call.param("name");
  auto text = find_builtin_scene(name);
  if (!text)
    return {"/v1/scenes/{name}",
            problem(call.request, http::status::not_found, "Not found",
                    "no built-in scene \"" + std::string(name) + "\" (GET /v1/scenes lists them)")};
  return {"/v1/scenes/{name}", json_answer(call.request, http::status::ok, std::string(*text))};
}

Routed Api::jobs(const Call& call) {
  return {"/v1/jobs", json_answer(call.request, http::status::ok, jobs_to_json(store_.list()))};
}

Routed Api::submit_job(const Call&) {
  return {"/v1/jobs",
          DeferredRequest{DeferredRequest::Pool::Parse,
                          [this](const Request& r, std::stop_source) { return submit(r); }}};
}

Routed Api::validate_job(const Call&) {
  return {"/v1/validate",
          DeferredRequest{DeferredRequest::Pool::Parse,
                          [this](const Request& r, std::stop_source) { return validate(r); }}};
}

Routed Api::with_job(const Call& call, JobHandler then) {
  const std::string id(call.param("id"));
  const std::optional<JobRecord> found = is_valid_job_id(id) ? store_.find(id) : std::nullopt;
  if (!found) return not_found(call);
  return (this->*then)(call, *found);
}

Routed Api::not_found(const Call& call) const {
  return {std::string(call.pattern),
          problem(call.request, http::status::not_found, "Not found",
                  "no job with id \"" + std::string(call.param("id")) + "\"")};
}

namespace {

Routed not_done(const Request& request, std::string_view route, const JobRecord& record,
                std::string_view what) {
  return {std::string(route),
          problem(request, http::status::conflict, "Job not done",
                  "job " + record.id + " is " + std::string(to_string(record.state)) + "; " +
                      std::string(what) + " exists only for done jobs")};
}

}  // namespace

Routed Api::job(const Call& call, const JobRecord& record) {
  return {std::string(call.pattern),
          json_answer(call.request, http::status::ok, job_to_json(record))};
}

Routed Api::delete_job(const Call& call, const JobRecord& record) {
  const std::string route(call.pattern);
  switch (store_.cancel_or_delete(record.id)) {
    case Store::Removal::Cancelled:
      return {route, json_answer(call.request, http::status::accepted,
                                 job_to_json(store_.find(record.id).value_or(record)))};
    case Store::Removal::Deleted:
      return {route, answer(call.request, http::status::no_content, "application/json", "")};
    case Store::Removal::Unknown:
      break;
  }
  return not_found(call);
}

Routed Api::retexture_job(const Call& call, const JobRecord& record) {
  if (record.state != JobState::Done)
    return not_done(call.request, call.pattern, record, "a perturbed radiosity map");
  // Parsing, loading a solution that is not in memory, and rendering all happen on the
  // render pool: a network thread never waits for them.
  return {std::string(call.pattern),
          DeferredRequest{DeferredRequest::Pool::Render,
                          [this, id = record.id](const Request& r, std::stop_source stop) {
                            return retexture(r, id, std::move(stop));
                          }}};
}

Routed Api::job_events(const Call& call, const JobRecord& record) {
  auto job = live_.watch(record.id);
  if (!job) return not_found(call);
  const bool images = call.pattern.ends_with("/stream");
  return {std::string(call.pattern),
          StreamRequest{job, images ? StreamRequest::Kind::Images : StreamRequest::Kind::Events}};
}

Routed Api::step_answer(const Call& call, const JobRecord& record, int step, bool immutable) {
  const std::string route(call.pattern);
  if (step < 1 || step > record.step)
    return {route, problem(call.request, http::status::not_found, "Not found",
                           "job " + record.id + " has no step " + std::to_string(step) +
                               " (steps 1.." + std::to_string(record.step) + " so far)")};
  if (step < record.first_kept_step)
    return {route, problem(call.request, http::status::gone, "Step dropped",
                           "step " + std::to_string(step) + " is no longer kept (kept: " +
                               std::to_string(record.first_kept_step) + ".." +
                               std::to_string(record.step) + ")")};
  auto png = store_.read_step(record.id, step);
  if (!png)
    return {route, problem(call.request, http::status::gone, "Step dropped",
                           "step " + std::to_string(step) + " is no longer kept")};
  return {route, png_answer(call.request, std::move(*png), step, immutable)};
}

Routed Api::job_step(const Call& call, const JobRecord& record) {
  const auto step = to_int(call.param("n"));
  if (!step) return not_found(call);
  return step_answer(call, record, *step, true);
}

Routed Api::job_preview(const Call& call, const JobRecord& record) {
  if (auto s = query_value(call.query, "step")) {
    auto step = to_int(*s);
    if (!step)
      return {std::string(call.pattern),
              problem(call.request, http::status::bad_request, "Bad query",
                      "step must be an integer (got \"" + std::string(*s) + "\")", "step")};
    return step_answer(call, record, *step, false);
  }
  auto png = record.step > 0 ? store_.read_step(record.id, record.step) : std::nullopt;
  if (!png)
    return {std::string(call.pattern),
            problem(call.request, http::status::not_found, "No preview yet",
                    "job " + record.id + " is " + std::string(to_string(record.state)) +
                        " and has no refinement step yet")};
  return {std::string(call.pattern), png_answer(call.request, std::move(*png), record.step, false)};
}

Routed Api::job_scene(const Call& call, const JobRecord& record) {
  auto text = store_.read(record.id, Artifact::Scene);
  if (!text) return not_found(call);
  return {std::string(call.pattern), json_answer(call.request, http::status::ok, std::move(*text))};
}

Routed Api::job_solution(const Call& call, const JobRecord& record) {
  if (record.state != JobState::Done)
    return not_done(call.request, call.pattern, record, "the solution file");
  auto bytes = store_.read(record.id, Artifact::Solution);
  if (!bytes) return not_found(call);
  store_.touch(record.id);
  Response res =
      answer(call.request, http::status::ok, "application/octet-stream", std::move(*bytes));
  res.set(http::field::content_disposition, "attachment; filename=\"" + record.id + ".bumprad\"");
  return {std::string(call.pattern), std::move(res)};
}

Routed Api::job_model(const Call& call, const JobRecord& record) {
  if (record.state != JobState::Done)
    return not_done(call.request, call.pattern, record, "the lit model");
  // Loading the solution and writing the model happen on the render pool.
  return {std::string(call.pattern),
          DeferredRequest{DeferredRequest::Pool::Render,
                          [this, id = record.id](const Request& request, std::stop_source) {
                            try {
                              auto solved = solutions_.get(id);
                              if (!solved)
                                return problem(request, http::status::not_found, "Not found",
                                               "job " + id + " was deleted");
                              store_.touch(id);
                              Response res = answer(request, http::status::ok, "model/gltf-binary",
                                                    export_glb(solved->scene, solved->solution));
                              res.set(http::field::content_disposition,
                                      "attachment; filename=\"" + id + ".glb\"");
                              return res;
                            } catch (...) {
                              return refusal(request, std::current_exception());
                            }
                          }}};
}

Routed Api::job_image(const Call& call, const JobRecord& record) {
  std::string_view format = query_value(call.query, "format").value_or("png");
  if (format != "png" && format != "exr")
    return {std::string(call.pattern),
            problem(call.request, http::status::bad_request, "Bad query",
                    "format must be png or exr (got \"" + std::string(format) + "\")", "format")};
  if (record.state != JobState::Done)
    return not_done(call.request, call.pattern, record, "the final image");
  ImageFormat f = format == "png" ? ImageFormat::Png : ImageFormat::Exr;
  auto bytes = store_.read(record.id, f == ImageFormat::Png ? Artifact::Png : Artifact::Exr);
  if (!bytes) return not_found(call);
  store_.touch(record.id);
  // Saved, the image is named for its job and format (not "image").
  Response res = answer(call.request, http::status::ok, mime_type(f), std::move(*bytes));
  res.set(http::field::content_disposition,
          "inline; filename=\"" + record.id + (f == ImageFormat::Png ? ".png\"" : ".exr\""));
  return {std::string(call.pattern), std::move(res)};
}

Api::Accepted Api::accept(const Request& request) const {
  JobRequest job_request = parse_job_request(
      job_request_json(request[http::field::content_type], request.body()), limits_.files);
  const bool inline_scene = job_request.inline_scene;
  const CostEstimate cost = estimate_cost(job_request.scene);
  if (cost.solve_s + cost.render_s > limits_.max_job_seconds) {
    const bool solve = cost.solve_s >= cost.render_s;
    throw SceneError(
        solve ? (inline_scene ? "/scene/solver" : "/solver")
              : (inline_scene ? "/scene/camera" : "/builtin"),
        "this job would take about " + describe_duration(cost.solve_s + cost.render_s) +
            (solve ? " to solve (" + cost.solve_terms + ")"
                   : " to render (" + cost.render_terms + ")") +
            ", over this server's limit of " + describe_duration(limits_.max_job_seconds) +
            " (--max-job-seconds)" +
            (solve
                 ? "; lower max_shots or hemicube_resolution, or raise element_size"
                 : "; lower the camera's width, height, antialias, glossy_samples or shadow_rays"));
  }
  return {std::move(job_request), cost};
}

Response Api::validate(const Request& request) {
  try {
    const CostEstimate cost = accept(request).cost;
    return json_answer(request, http::status::ok,
                       validation_json(cost.solve_s, cost.render_s, limits_.max_job_seconds));
  } catch (...) {
    return refusal(request, std::current_exception());
  }
}

Response Api::submit(const Request& request) {
  try {
    const std::string_view key = request[kIdempotencyKey];
    if (key.size() > 255 || key.find_first_not_of(kKeyCharacters) != std::string_view::npos)
      return problem(request, http::status::bad_request, "Bad header",
                     "Idempotency-Key must be 1 to 255 printable ASCII characters",
                     kIdempotencyKey);
    JobRequest job = accept(request).job;
    JobRecord r;
    r.id = new_job_id();
    r.scene_name = job.scene_name;
    r.created = unix_now();
    r.max_shots = job.scene.solver.max_shots;
    r.preview_every = job.scene.solver.preview_every;
    r.warnings = job.warnings;
    const Store::Submitted submitted = store_.submit(r, job.scene_json, key);
    Response res = json_answer(request, http::status::accepted, job_to_json(submitted.record));
    res.set(http::field::location, job_url(submitted.record.id));
    if (!submitted.created) res.set("Idempotent-Replayed", "true");
    return res;
  } catch (...) {
    return refusal(request, std::current_exception());
  }
}

Response Api::retexture(const Request& request, const std::string& id, std::stop_source stop) {
  Watchdog::Guard deadline(watchdog_, stop,
                           std::chrono::duration<double>(limits_.retexture_timeout_s));
  try {
    auto solved = solutions_.get(id);
    if (!solved)
      return problem(request, http::status::not_found, "Not found", "job " + id + " was deleted");
    store_.touch(id);
    RetextureRequest r = parse_retexture_request(request.body(), solved->scene, limits_.files);
    const CostEstimate cost = estimate_render_cost(r.scene);
    if (cost.render_s > limits_.max_retexture_seconds)
      throw SceneError("/camera", "this re-texture would take about " +
                                      describe_duration(cost.render_s) + " to render (" +
                                      cost.render_terms + "), over this server's limit of " +
                                      describe_duration(limits_.max_retexture_seconds) +
                                      " (--max-retexture-seconds); lower width, height, antialias, "
                                      "glossy_samples or shadow_rays");
    Image image =
        solutions_.view(id, solved, r.scene.camera)->render(r.scene.bumps, stop.get_token());
    if (stop.stop_requested()) {
      Response res =
          problem(request, http::status::service_unavailable, "Stopped",
                  deadline.timed_out()
                      ? "the re-texture ran past this server's time limit of " +
                            describe_duration(limits_.retexture_timeout_s) +
                            "; try again when it is less busy"
                      : std::string("the client went away or the server is shutting down"));
      res.set(http::field::retry_after, "5");
      return res;
    }
    return answer(request, http::status::ok, mime_type(r.format),
                  encode_image(image, r.format, r.scene.camera.exposure));
  } catch (...) {
    return refusal(request, std::current_exception());
  }
}

}  // namespace bumprad
