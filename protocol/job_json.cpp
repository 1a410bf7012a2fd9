#include "protocol/job_json.h"

#include <array>
#include <limits>

#include <nlohmann/json.hpp>

#include "protocol/json_node.h"

namespace bumprad {
namespace {

using json = nlohmann::json;

constexpr std::array<std::string_view, 6> kStateNames = {"queued", "running",   "done",
                                                         "failed", "cancelled", "interrupted"};

}  // namespace

std::string_view to_string(JobState state) {
  return kStateNames[std::size_t(state)];
}

std::optional<JobState> job_state_from(std::string_view name) {
  for (std::size_t i = 0; i < kStateNames.size(); ++i)
    if (kStateNames[i] == name) return JobState(i);
  return std::nullopt;
}

bool is_finished(JobState state) {
  return state != JobState::Queued && state != JobState::Running;
}

std::string job_url(const std::string& id) {
  return "/v1/jobs/" + id;
}

std::string step_url(const std::string& id, int step) {
  return job_url(id) + "/steps/" + std::to_string(step) + ".png";
}

namespace {

json job_document(const JobRecord& j, bool with_history) {
  const std::string self = job_url(j.id);
  json links = {{"self", self},
                {"preview", self + "/preview"},
                {"stream", self + "/stream"},
                {"events", self + "/events"},
                {"scene", self + "/scene"}};
  if (j.state == JobState::Done) {
    links["image"] = self + "/image";
    links["retexture"] = self + "/retexture";
  }
  json d = {{"id", j.id},
            {"state", to_string(j.state)},
            {"scene", j.scene_name},
            {"created_at", j.created},
            {"started_at", j.started},
            {"finished_at", j.finished},
            {"shots", j.shots},
            {"max_shots", j.max_shots},
            {"preview_every", j.preview_every},
            {"unshot_fraction", j.unshot_fraction},
            {"step", j.step},
            {"first_kept_step", j.first_kept_step},
            {"elements", j.elements},
            {"patches", j.patches},
            {"timings",
             {{"solve_s", j.seconds_solve},
              {"texture_s", j.seconds_texture},
              {"previews_s", j.seconds_previews}}},
            {"links", links}};
  if (j.step > 0) d["latest_step_url"] = step_url(j.id, j.step);
  if (j.estimated_error > 0)
    d["estimated_error"] = {{"relative_rms", j.estimated_error},
                            {"standard_error", j.estimated_error_se}};
  if (j.antialias > 0) d["antialias"] = j.antialias;
  if (!j.error.empty()) d["error"] = j.error;
  if (!j.warnings.empty()) d["warnings"] = j.warnings;
  if (with_history && !j.history.empty()) {
    json points = json::array();
    for (const ProgressPoint& p : j.history) points.push_back({p.shots, p.seconds, p.unshot});
    d["history"] = points;  // [shots, seconds, unshot] a step
  }
  return d;
}

}  // namespace

void add_progress(JobRecord& job, const ProgressPoint& point) {
  auto& h = job.history;
  if (h.size() >= JobRecord::kMaxHistory) {
    std::size_t kept = 1;  // the first point stays; of the rest, every other
    for (std::size_t i = 2; i < h.size(); i += 2) h[kept++] = h[i];
    h.resize(kept);
  }
  h.push_back(point);
}

std::string job_to_json(const JobRecord& job) {
  return job_document(job, true).dump();
}

std::string jobs_to_json(const std::vector<JobRecord>& jobs) {
  json list = json::array();
  for (const JobRecord& j : jobs) list.push_back(job_document(j, false));
  return json{{"jobs", list}}.dump();
}

std::vector<JobRecord> jobs_from_json(std::string_view text) {
  const json d = parse_json(text);
  const auto list = d.find("jobs");
  if (!d.is_object() || list == d.end() || !list->is_array())
    throw MalformedJson("a job list is an object with a \"jobs\" array");
  std::vector<JobRecord> jobs;
  for (const json& j : *list) jobs.push_back(job_from_json(j.dump()));
  return jobs;
}

JobRecord job_from_json(std::string_view text) {
  // Through Node like a request: a record is data from disk, and a number out of range
  // must be an error, not a conversion with undefined behaviour.
  json d = parse_json(text);
  const Node n(d, "");
  constexpr long long kMaxInt = std::numeric_limits<int>::max();
  JobRecord j;
  j.id = n["id"].string();
  auto state = job_state_from(n["state"].string());
  if (!state) n["state"].fail("unknown job state");
  j.state = *state;
  j.scene_name = n["scene"].string();
  j.created = n["created_at"].number();
  j.started = n["started_at"].number();
  j.finished = n["finished_at"].number();
  j.shots = int(n["shots"].integer(0, kMaxInt));
  j.max_shots = int(n["max_shots"].integer(0, kMaxInt));
  j.preview_every = int(n["preview_every"].integer(0, kMaxInt));
  j.unshot_fraction = n["unshot_fraction"].number();
  j.step = int(n["step"].integer(0, kMaxInt));
  j.first_kept_step = int(n["first_kept_step"].integer(0, kMaxInt));
  j.elements = std::size_t(n["elements"].integer(0, kMaxInt));
  j.patches = std::size_t(n["patches"].integer(0, kMaxInt));
  const Node t = n["timings"];
  j.seconds_solve = t["solve_s"].number();
  j.seconds_texture = t["texture_s"].number();
  j.seconds_previews = t["previews_s"].number();
  if (auto e = n.get("estimated_error")) {
    j.estimated_error = (*e)["relative_rms"].number();
    j.estimated_error_se = (*e)["standard_error"].number();
  }
  if (auto a = n.get("antialias")) j.antialias = int(a->integer(1, kMaxInt));
  if (auto e = n.get("error")) j.error = e->string();
  if (auto w = n.get("warnings"))
    for (std::size_t i = 0, count = w->array(0, 10'000); i < count; ++i)
      j.warnings.push_back((*w)[i].string());
  if (auto h = n.get("history"))
    for (std::size_t i = 0, count = h->array(0, JobRecord::kMaxHistory); i < count; ++i) {
      const Node p = (*h)[i];
      p.array(3, 3);
      j.history.push_back({int(p[0].integer(0, kMaxInt)), p[1].number(), p[2].number()});
    }
  return j;
}

std::string step_event_json(const JobRecord& j) {
  return json{{"step", j.step},
              {"shots", j.shots},
              {"max_shots", j.max_shots},
              {"unshot_fraction", j.unshot_fraction},
              {"preview", step_url(j.id, j.step)}}
      .dump();
}

StepEvent step_event_from_json(std::string_view text) {
  json d = parse_json(text);
  const Node n(d, "");
  constexpr long long kMaxInt = std::numeric_limits<int>::max();
  return {int(n["step"].integer(0, kMaxInt)), int(n["shots"].integer(0, kMaxInt)),
          int(n["max_shots"].integer(0, kMaxInt)), n["unshot_fraction"].number(),
          n["preview"].string()};
}

namespace {

json parse_part(std::string_view text, const char* what) {
  try {
    return parse_json(text);
  } catch (const MalformedJson& e) {
    throw MalformedJson(std::string(what) + ": " + e.reason());
  }
}

}  // namespace

std::string job_request_json(const JobSubmission& s) {
  json request = json::object();
  if (s.scene_json.empty())
    request["builtin"] = s.builtin;
  else
    request["scene"] = parse_part(s.scene_json, "the scene");
  if (!s.bumps_json.empty()) request["bumps"] = parse_part(s.bumps_json, "the bump file");
  if (s.max_shots) request["solver"]["max_shots"] = *s.max_shots;
  if (s.preview_every) request["preview_every"] = *s.preview_every;
  return request.dump();
}

std::string retexture_request_json(std::string_view bumps_json, ImageFormat format) {
  json request = {{"format", format_name(format)}};
  if (!bumps_json.empty()) request["bumps"] = parse_part(bumps_json, "the bump file");
  return request.dump();
}

std::string valid_utf8(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char b = byte(i);
    // The length of a well-formed sequence starting here (RFC 3629: no overlong forms, no
    // surrogates, nothing above U+10FFFF), or 0.
    std::size_t n = b < 0x80                 ? 1
                    : b >= 0xC2 && b <= 0xDF ? 2
                    : b >= 0xE0 && b <= 0xEF ? 3
                    : b >= 0xF0 && b <= 0xF4 ? 4
                                             : 0;
    if (n > text.size() - i) n = 0;
    for (std::size_t k = 1; k < n; ++k) {
      unsigned char lo = 0x80, hi = 0xBF;
      if (k == 1 && b == 0xE0) lo = 0xA0;
      if (k == 1 && b == 0xED) hi = 0x9F;
      if (k == 1 && b == 0xF0) lo = 0x90;
      if (k == 1 && b == 0xF4) hi = 0x8F;
      if (byte(i + k) < lo || byte(i + k) > hi) n = 0;
    }
    if (n == 0) {
      constexpr char kHex[] = "0123456789ABCDEF";
      out += "\\x";
      out += kHex[b >> 4];
      out += kHex[b & 15];
      ++i;
      continue;
    }
    out.append(text.substr(i, n));
    i += n;
  }
  return out;
}

std::string problem_json(int status, std::string_view title, std::string_view detail,
                         std::string_view field) {
  json p = {{"type", "about:blank"},
            {"title", title},
            {"status", status},
            {"detail", valid_utf8(detail)}};
  if (!field.empty()) p["field"] = valid_utf8(field);
  return p.dump();
}

}  // namespace bumprad
