#include "server/api.h"

#include <charconv>
#include <cstdio>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/stopwatch.h"
#include "protocol/api_json.h"
#include "protocol/builtin_scenes.h"
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

Response method_not_allowed(const Request& request, std::string_view allowed) {
  Response res = problem(
      request, http::status::method_not_allowed, "Method not allowed",
      std::string(request.method_string()) + " is not allowed here; use " + std::string(allowed));
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

}  // namespace

Routed Api::handle(const Request& request) {
  Routed routed;
  try {
    routed = route(request);
  } catch (const std::exception& e) {
    routed = {"(error)", internal_error(request, e.what())};
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

Routed Api::route(const Request& request) {
  std::string_view target = request.target();
  std::string_view path = target.substr(0, target.find('?'));
  std::string_view query =
      target.find('?') == std::string_view::npos ? "" : target.substr(target.find('?') + 1);
  const auto parts = split_path(path);
  const http::verb method = request.method();
  // HEAD is answered as GET; handle() drops the body.
  const bool get = method == http::verb::get || method == http::verb::head;

  if (auto asset = find_web_asset(path)) {
    if (!get) return {std::string(path), method_not_allowed(request, "GET, HEAD")};
    std::string type(asset->content_type);
    if (type.starts_with("text/")) type += "; charset=utf-8";
    return {std::string(path), answer(request, http::status::ok, type, std::string(asset->body))};
  }
  if (path == "/healthz") {
    if (!get) return {"/healthz", method_not_allowed(request, "GET, HEAD")};
    if (auto trouble = store_.health())
      return {"/healthz", json_answer(request, http::status::service_unavailable,
                                      R"({"status":"unavailable","store":)" +
                                          nlohmann::json(valid_utf8(*trouble)).dump() + "}")};
    return {"/healthz", json_answer(request, http::status::ok, R"({"status":"ok","store":"ok"})")};
  }
  if (path == "/metrics") {
    if (!get) return {"/metrics", method_not_allowed(request, "GET, HEAD")};
    Metrics::Gauges gauges;
    gauges.store_up = !store_.health();
    if (gauges.store_up) gauges.jobs_by_state = store_.counts().jobs_by_state;
    gauges.queue_capacity = store_.options().max_queue;
    gauges.workers = workers_;
    return {"/metrics", answer(request, http::status::ok, "text/plain; version=0.0.4",
                               metrics_.prometheus(gauges))};
  }
  if (path == "/v1/scenes") {
    if (!get) return {"/v1/scenes", method_not_allowed(request, "GET, HEAD")};
    return {"/v1/scenes", json_answer(request, http::status::ok, builtin_scenes_json())};
  }
  if (path == "/v1/jobs") {
    if (get)
      return {"/v1/jobs", json_answer(request, http::status::ok, jobs_to_json(store_.list()))};
    if (method != http::verb::post)
      return {"/v1/jobs", method_not_allowed(request, "GET, HEAD, POST")};
    return {"/v1/jobs",
            DeferredRequest{DeferredRequest::Pool::Parse,
                            [this](const Request& r, std::stop_source) { return submit(r); }}};
  }

  if (path == "/v1/validate") {
    if (method != http::verb::post) return {"/v1/validate", method_not_allowed(request, "POST")};
    return {"/v1/validate",
            DeferredRequest{DeferredRequest::Pool::Parse,
                            [this](const Request& r, std::stop_source) { return validate(r); }}};
  }
  if (parts.size() == 3 && parts[0] == "v1" && parts[1] == "scenes") {
    if (!get) return {"/v1/scenes/{name}", method_not_allowed(request, "GET, HEAD")};
    auto text = find_builtin_scene(parts[2]);
    if (!text)
      return {"/v1/scenes/{name}", problem(request, http::status::not_found, "Not found",
                                           "no built-in scene \"" + std::string(parts[2]) +
                                               "\" (GET /v1/scenes lists them)")};
    return {"/v1/scenes/{name}", json_answer(request, http::status::ok, std::string(*text))};
  }
  if (parts.size() < 3 || parts[0] != "v1" || parts[1] != "jobs")
    return {"(unknown)", problem(request, http::status::not_found, "Not found",
                                 "no such resource: " + std::string(path))};
  const std::string id(parts[2]);
  const std::optional<JobRecord> found = is_valid_job_id(id) ? store_.find(id) : std::nullopt;
  const std::string sub = parts.size() > 3 ? std::string(parts[3]) : "";
  const std::string route = "/v1/jobs/{id}" + (sub.empty() ? "" : "/" + sub);
  auto not_found = [&] {
    return Routed{route, problem(request, http::status::not_found, "Not found",
                                 "no job with id \"" + id + "\"")};
  };
  if (!found || parts.size() > 5 || (parts.size() == 5 && sub != "steps")) return not_found();
  const JobRecord& record = *found;
  auto not_done = [&](std::string_view what) {
    return Routed{route, problem(request, http::status::conflict, "Job not done",
                                 "job " + id + " is " + std::string(to_string(record.state)) +
                                     "; " + std::string(what) + " exists only for done jobs")};
  };

  if (sub.empty()) {
    if (get) return {route, json_answer(request, http::status::ok, job_to_json(record))};
    if (method != http::verb::delete_)
      return {route, method_not_allowed(request, "GET, HEAD, DELETE")};
    switch (store_.cancel_or_delete(id)) {
      case Store::Removal::Cancelled:
        return {route, json_answer(request, http::status::accepted,
                                   job_to_json(store_.find(id).value_or(record)))};
      case Store::Removal::Deleted:
        return {route, answer(request, http::status::no_content, "application/json", "")};
      case Store::Removal::Unknown:
        return not_found();
    }
  }
  if (sub == "retexture") {
    if (method != http::verb::post) return {route, method_not_allowed(request, "POST")};
    if (record.state != JobState::Done) return not_done("a perturbed radiosity map");
    // Parsing, loading a solution that is not in memory, and rendering all happen on the
    // render pool: a network thread never waits for them.
    return {route, DeferredRequest{DeferredRequest::Pool::Render,
                                   [this, id](const Request& r, std::stop_source stop) {
                                     return retexture(r, id, std::move(stop));
                                   }}};
  }
  if (!get) return {route, method_not_allowed(request, "GET, HEAD")};
  if (sub == "stream" || sub == "events") {
    auto job = live_.watch(id);
    if (!job) return not_found();
    return {route, StreamRequest{job, sub == "stream" ? StreamRequest::Kind::Images
                                                      : StreamRequest::Kind::Events}};
  }
  auto step_answer = [&](int step, bool immutable) -> Routed {
    if (step < 1 || step > record.step)
      return {route, problem(request, http::status::not_found, "Not found",
                             "job " + id + " has no step " + std::to_string(step) + " (steps 1.." +
                                 std::to_string(record.step) + " so far)")};
    if (step < record.first_kept_step)
      return {route, problem(request, http::status::gone, "Step dropped",
                             "step " + std::to_string(step) + " is no longer kept (kept: " +
                                 std::to_string(record.first_kept_step) + ".." +
                                 std::to_string(record.step) + ")")};
    auto png = store_.read_step(id, step);
    if (!png)
      return {route, problem(request, http::status::gone, "Step dropped",
                             "step " + std::to_string(step) + " is no longer kept")};
    return {route, png_answer(request, std::move(*png), step, immutable)};
  };
  if (sub == "steps") {
    std::string_view name = parts.size() == 5 ? parts[4] : "";
    auto step = name.ends_with(".png") ? to_int(name.substr(0, name.size() - 4)) : std::nullopt;
    if (!step) return not_found();
    return step_answer(*step, true);
  }
  if (sub == "preview") {
    if (auto s = query_value(query, "step")) {
      auto step = to_int(*s);
      if (!step)
        return {route,
                problem(request, http::status::bad_request, "Bad query",
                        "step must be an integer (got \"" + std::string(*s) + "\")", "step")};
      return step_answer(*step, false);
    }
    auto png = record.step > 0 ? store_.read_step(id, record.step) : std::nullopt;
    if (!png)
      return {route, problem(request, http::status::not_found, "No preview yet",
                             "job " + id + " is " + std::string(to_string(record.state)) +
                                 " and has no refinement step yet")};
    return {route, png_answer(request, std::move(*png), record.step, false)};
  }
  if (sub == "scene") {
    auto text = store_.read(id, Artifact::Scene);
    if (!text) return not_found();
    return {route, json_answer(request, http::status::ok, std::move(*text))};
  }
  if (sub == "solution") {
    if (record.state != JobState::Done) return not_done("the solution file");
    auto bytes = store_.read(id, Artifact::Solution);
    if (!bytes) return not_found();
    store_.touch(id);
    Response res = answer(request, http::status::ok, "application/octet-stream", std::move(*bytes));
    res.set(http::field::content_disposition, "attachment; filename=\"" + id + ".bumprad\"");
    return {route, std::move(res)};
  }
  if (sub == "image") {
    std::string_view format = query_value(query, "format").value_or("png");
    if (format != "png" && format != "exr")
      return {route,
              problem(request, http::status::bad_request, "Bad query",
                      "format must be png or exr (got \"" + std::string(format) + "\")", "format")};
    if (record.state != JobState::Done) return not_done("the final image");
    ImageFormat f = format == "png" ? ImageFormat::Png : ImageFormat::Exr;
    auto bytes = store_.read(id, f == ImageFormat::Png ? Artifact::Png : Artifact::Exr);
    if (!bytes) return not_found();
    store_.touch(id);
    return {route, answer(request, http::status::ok, mime_type(f), std::move(*bytes))};
  }
  return not_found();
}

Api::Accepted Api::accept(const Request& request) const {
  JobRequest job_request = parse_job_request(request.body(), limits_.files);
  const bool inline_scene = job_request.scene_name == "inline";
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
  } catch (const SceneError& e) {
    return scene_problem(request, e);
  } catch (const std::exception& e) {
    return internal_error(request, e.what());
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
    const Store::Submitted submitted = store_.submit(r, job.scene_json, key);
    Response res = json_answer(request, http::status::accepted, job_to_json(submitted.record));
    res.set(http::field::location, job_url(submitted.record.id));
    if (!submitted.created) res.set("Idempotent-Replayed", "true");
    return res;
  } catch (const SceneError& e) {
    return scene_problem(request, e);
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
  } catch (const std::exception& e) {
    return internal_error(request, e.what());
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
    Image image = render(r.scene, solved->solution, stop.get_token());
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
  } catch (const SceneError& e) {
    return scene_problem(request, e);
  } catch (const std::exception& e) {
    return internal_error(request, e.what());
  }
}

}  // namespace bumprad
