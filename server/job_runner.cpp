#include "server/job_runner.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "common/stopwatch.h"
#include "protocol/solution_file.h"
#include "solver/render/back_faces.h"
#include "solver/scene/camera.h"
#include "solver/solution.h"
#include "solver/util/image.h"

namespace bumprad {
namespace {

// Draft previews take at most this share of a job's time: a step that comes sooner shows
// in the next preview.
constexpr double kPreviewShare = 0.25;
// A tolerance's extra adaptive levels (solve()) must end within this share of the job's time
// limit: the final image and its storing take the rest.
constexpr double kRefineShare = 0.75;
// A step without a preview reaches the store at most this often: a lease (seconds long) and a
// progress bar need no more, and in a farm the database takes every worker's writes.
constexpr double kProgressInterval = 0.1;
// While the job database is unreachable a worker keeps its job: the solve goes on, and the
// store is tried again after a backoff that doubles from the first to the last of these.
constexpr double kFirstBackoff = 0.25, kLastBackoff = 4;

}  // namespace

// One attempt at one job, from claim to its end: its record as the store will see it, and
// what it has heard (a lost lease, a cancel) on the way.
class JobRunner::Attempt {
 public:
  Attempt(JobRunner& runner, const std::string& worker, const Claim& claim, std::stop_source stop,
          const std::atomic<StopReason>& reason)
      : runner_(runner),
        worker_(worker),
        record_(claim.record),
        stop_(std::move(stop)),
        reason_(reason),
        deadline_(runner.watchdog_, stop_,
                  std::chrono::duration<double>(runner.options_.job_timeout_s)) {}

  void run(const std::string& scene_json);

 private:
  // A refinement step: progress to the store, and a draft preview while previews have
  // taken less than their share of the time. False stops the solve.
  bool step(const Snapshot& snap, const Solution& partial);
  // A step renews the lease; a step with a preview stores it and wakes the watchers. While
  // the database is unreachable, steps wait out the backoff and the solve goes on.
  void report(const std::string& png);
  void renew(const std::string& png);
  // Writes the job's end (`write` calls the store), trying again after each backoff while
  // the database is unreachable, until it lands or the worker shuts down (the job then
  // waits for its lease to run out, as it would for a worker that vanished).
  template <typename Write>
  void until_stored(Write write);
  void store_lost(const StoreUnavailable& e);
  void store_back();
  // A stopped job ends cancelled (DELETE), released (shutdown) or failed (time limit).
  void stopped(const SolveStats& stats);
  // The final image, the solution file and the record, done.
  void finish(const Scene& scene, const std::string& scene_json, const Solution& solution);

  JobRunner& runner_;
  const std::string& worker_;
  JobRecord record_;
  std::stop_source stop_;
  const std::atomic<StopReason>& reason_;
  Watchdog::Guard deadline_;
  bool lease_lost_ = false, cancel_heard_ = false;
  Scene draft_;  // the scene at the drafts' camera (its exposure too)
  Clock::time_point started_ = Clock::now(), last_step_ = started_, last_write_ = started_;
  int last_shots_ = 0;
  double drafts_s_ = 0;  // inside the solve's wall time, reported apart
  bool store_down_ = false;
  Clock::time_point retry_at_;
  double backoff_s_ = kFirstBackoff;
};

void JobRunner::run(const std::string& worker, const Claim& claim, std::stop_source stop,
                    const std::atomic<StopReason>& reason) {
  metrics_.count_claim();
  std::fprintf(stderr, "job %s claimed by %s\n", claim.record.id.c_str(), worker.c_str());
  Attempt(*this, worker, claim, std::move(stop), reason).run(claim.scene_json);
}

void JobRunner::Attempt::run(const std::string& scene_json) {
  try {
    const Scene scene = parse_scene(std::string_view(scene_json), runner_.options_.files);
    draft_ = scene;
    draft_.camera = draft_camera(scene.camera);
    started_ = last_step_ = last_write_ = Clock::now();
    record_.history.clear();  // a job claimed again solves from the start
    Solution solution = solve(
        scene,
        [this](const Snapshot& snap, const Solution& partial) { return step(snap, partial); },
        stop_.get_token(), kRefineShare * runner_.options_.job_timeout_s);
    if (stop_.stop_requested()) return stopped(solution.stats);
    finish(scene, scene_json, solution);
  } catch (const std::exception& e) {
    if (lease_lost_) return;
    record_.state = JobState::Failed;
    record_.error = e.what();
    until_stored([&] { runner_.store_.finish(worker_, record_, nullptr); });
  }
}

bool JobRunner::Attempt::step(const Snapshot& snap, const Solution& partial) {
  runner_.metrics_.count_shots(snap.shots - last_shots_, seconds_since(last_step_));
  last_shots_ = snap.shots;
  if (snap.final) {  // its image is finish()'s; the curve ends here
    add_progress(record_, {snap.shots, seconds_since(started_), snap.unshot_fraction});
    return true;
  }
  record_.shots = snap.shots;
  record_.unshot_fraction = snap.unshot_fraction;
  add_progress(record_, {snap.shots, seconds_since(started_), snap.unshot_fraction});
  record_.elements = partial.mesh->elements.size();
  record_.patches = partial.mesh->patches.size();
  std::string png;
  if (record_.step == 0 || record_.seconds_previews < kPreviewShare * seconds_since(started_)) {
    auto t = Clock::now();
    Image preview = render(draft_, partial, snap, stop_.get_token());
    if (stop_.stop_requested()) return false;
    png = encode_image(preview, ImageFormat::Png, draft_.camera.exposure);
    record_.seconds_previews += seconds_since(t);
    drafts_s_ += seconds_since(t);
  }
  report(png);
  last_step_ = Clock::now();
  return !stop_.stop_requested();
}

void JobRunner::Attempt::report(const std::string& png) {
  if (png.empty() && seconds_since(last_write_) < kProgressInterval) return;
  if (store_down_ && Clock::now() < retry_at_) return;
  last_write_ = Clock::now();
  try {
    renew(png);
  } catch (const StoreUnavailable& e) {
    store_lost(e);
  }
}

void JobRunner::Attempt::renew(const std::string& png) {
  const Store::Lease lease = runner_.store_.progress(worker_, record_, png);
  store_back();
  switch (lease) {
    case Store::Lease::Held:
      runner_.metrics_.count_lease_renewal();
      break;
    case Store::Lease::CancelRequested:
      cancel_heard_ = true;
      stop_.request_stop();
      break;
    case Store::Lease::Lost:
      lease_lost_ = true;
      stop_.request_stop();
      std::fprintf(stderr, "job %s: its lease was lost; another worker may run it\n",
                   record_.id.c_str());
      break;
  }
}

template <typename Write>
void JobRunner::Attempt::until_stored(Write write) {
  for (;;) {
    try {
      write();
      store_back();
      return;
    } catch (const StoreUnavailable& e) {
      store_lost(e);
    }
    while (Clock::now() < retry_at_) {
      if (reason_ == StopReason::Shutdown) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
}

void JobRunner::Attempt::store_lost(const StoreUnavailable& e) {
  if (!store_down_)
    std::fprintf(stderr, "job %s: %s; keeping the job and trying again\n", record_.id.c_str(),
                 e.what());
  else
    backoff_s_ = std::min(2 * backoff_s_, kLastBackoff);
  store_down_ = true;
  retry_at_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(backoff_s_));
}

void JobRunner::Attempt::store_back() {
  if (!store_down_) return;
  std::fprintf(stderr, "job %s: the job database answers again\n", record_.id.c_str());
  store_down_ = false;
  backoff_s_ = kFirstBackoff;
}

void JobRunner::Attempt::stopped(const SolveStats& stats) {
  if (lease_lost_) return;
  record_.shots = stats.shots;
  record_.unshot_fraction = stats.unshot_fraction;
  if (reason_ == StopReason::Shutdown && !cancel_heard_)
    return until_stored([&] { runner_.store_.release(worker_, record_); });
  if (deadline_.timed_out() && !cancel_heard_) {
    record_.state = JobState::Failed;
    char limit[32];
    std::snprintf(limit, sizeof limit, "%g s", runner_.options_.job_timeout_s);
    record_.error = std::string("the job ran past this server's time limit of ") + limit;
  } else {
    record_.state = JobState::Cancelled;
  }
  until_stored([&] { runner_.store_.finish(worker_, record_, nullptr); });
}

// The last step is the final image itself.
void JobRunner::Attempt::finish(const Scene& scene, const std::string& scene_json,
                                const Solution& solution) {
  auto t = Clock::now();
  Image image = render(scene, solution, stop_.get_token());
  if (stop_.stop_requested()) return stopped(solution.stats);
  Results results{encode_image(image, ImageFormat::Png, scene.camera.exposure),
                  encode_image(image, ImageFormat::Exr, 1), encode_solution(scene_json, solution)};
  record_.shots = solution.stats.shots;
  record_.unshot_fraction = solution.stats.unshot_fraction;
  record_.seconds_previews += seconds_since(t);
  for (std::string& w : back_face_warnings(scene, *solution.mesh, *solution.rays))
    record_.warnings.push_back(std::move(w));
  until_stored([&] { renew(results.png); });
  if (stop_.stop_requested()) return stopped(solution.stats);
  record_.state = JobState::Done;
  record_.elements = solution.stats.elements;
  record_.seconds_solve = solution.stats.seconds_solve - drafts_s_;
  record_.seconds_texture = solution.stats.seconds_texture;
  record_.estimated_error = solution.stats.estimated_error;
  record_.estimated_error_se = solution.stats.estimated_error_se;
  record_.antialias = rendered_antialias(scene, solution);
  until_stored([&] { runner_.store_.finish(worker_, record_, &results); });
}

}  // namespace bumprad
