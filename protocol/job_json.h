// The HTTP API's job JSON (protocol/openapi.json), which the client shares: job records as
// the API answers them and the stores keep them, step events, what the client sends, and
// problem details. It needs no solver: bumprad-client links only this and bumprad_common.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/image_format.h"
#include "protocol/json_parse.h"

namespace bumprad {

enum class JobState { Queued, Running, Done, Failed, Cancelled, Interrupted };

std::string_view to_string(JobState state);
std::optional<JobState> job_state_from(std::string_view name);
// Done, failed, cancelled and interrupted jobs do no more work.
bool is_finished(JobState state);

// One point of a job's convergence curve: after `shots` shots, `seconds` into its solve,
// `unshot` of the emitted power was still unshot.
struct ProgressPoint {
  int shots = 0;
  double seconds = 0, unshot = 1;
  bool operator==(const ProgressPoint&) const = default;
};

// What the server knows of one job. Times are Unix seconds; 0 means not yet.
struct JobRecord {
  std::string id;
  JobState state = JobState::Queued;
  std::string scene_name;  // "builtin:NAME" or "inline"
  double created = 0, started = 0, finished = 0;
  int shots = 0, max_shots = 0, preview_every = 0;
  double unshot_fraction = 1;
  int step = 0;             // the latest refinement step with a preview; 0: none yet
  int first_kept_step = 0;  // older step previews have been dropped
  std::size_t elements = 0, patches = 0;
  double seconds_solve = 0, seconds_texture = 0, seconds_previews = 0;
  // With solver.tolerance: the image's estimated relative RMS error against ground truth
  // and its standard error; 0 when not estimated.
  double estimated_error = 0, estimated_error_se = 0;
  // Once done: the rays a pixel across its images are rendered with (the camera's, or more
  // where a tolerance chose them); 0: not known yet.
  int antialias = 0;
  std::string error;  // why the job failed or was interrupted
  // What the job's models dropped or assumed (from the submission), and what its render
  // shows amiss (surfaces seen from behind, from the solve): one line each.
  std::vector<std::string> warnings;
  // Its convergence curve, a point per refinement step (thinned: at most kMaxHistory), so
  // that a job opened later, or elsewhere, draws it whole.
  std::vector<ProgressPoint> history;
  static constexpr std::size_t kMaxHistory = 256;
};

// Adds a point to `job`'s history; when it is full, every other point goes (the first and
// the newest stay), so the curve keeps its shape however many steps the solve takes.
void add_progress(JobRecord& job, const ProgressPoint& point);

std::string job_url(const std::string& id);
std::string step_url(const std::string& id, int step);

// The API's view of a job, with links to its resources. The server stores the same JSON.
std::string job_to_json(const JobRecord& job);
// Reads a stored record back. Throws MalformedJson or SceneError.
JobRecord job_from_json(std::string_view text);
// A JSON array of jobs, for GET /v1/jobs: their records without their histories.
std::string jobs_to_json(const std::vector<JobRecord>& jobs);
// The list GET /v1/jobs answers; throws as job_from_json does.
std::vector<JobRecord> jobs_from_json(std::string_view text);

// One refinement step, for the event stream: its number, progress and preview URL.
std::string step_event_json(const JobRecord& job);

struct StepEvent {
  int step = 0, shots = 0, max_shots = 0;
  double unshot_fraction = 1;
  std::string preview;  // the step's URL path
};
// Throws MalformedJson or SceneError.
StepEvent step_event_from_json(std::string_view text);

// The client's side of POST /v1/jobs: a built-in scene by name (`scene_json` empty) or an
// inline scene, with optional bump functions (a "bumps" block's JSON) and solver settings.
// Throws MalformedJson naming which text is not JSON.
struct JobSubmission {
  std::string builtin;
  std::string scene_json, bumps_json;
  std::optional<int> max_shots, preview_every;
};
std::string job_request_json(const JobSubmission& submission);
// The client's side of POST /v1/jobs/{id}/retexture.
std::string retexture_request_json(std::string_view bumps_json, ImageFormat format);

// `text` with every byte that is not part of well-formed UTF-8 written as \xNN, so that
// a message quoting a request's bytes can always be sent as JSON.
std::string valid_utf8(std::string_view text);

// RFC 9457 problem details; `field` (a JSON pointer) is added when the problem has one.
// The detail and field may quote the request's bytes: they are made valid UTF-8.
std::string problem_json(int status, std::string_view title, std::string_view detail,
                         std::string_view field = {});

}  // namespace bumprad
