#include "server/job_runner.h"

#include <algorithm>
#include <cstdio>

#include "common/stopwatch.h"
#include "protocol/solution_file.h"
#include "solver/scene/camera.h"
#include "solver/solution.h"
#include "solver/util/image.h"

namespace bumprad {
namespace {

// Draft previews take at most this share of a job's time: a step that comes sooner shows
// in the next preview.
constexpr double kPreviewShare = 0.25;
// A step without a preview reaches the store at most this often: a lease (seconds long) and a
// progress bar need no more, and in a farm the database takes every worker's writes.
constexpr double kProgressInterval = 0.1;

}  // namespace

void JobRunner::run(const std::string& worker, const Claim& claim, std::stop_source stop,
                    const std::atomic<StopReason>& reason) {
  metrics_.count_claim();
  JobRecord record = claim.record;
  std::fprintf(stderr, "job %s claimed by %s\n", record.id.c_str(), worker.c_str());
  Watchdog::Guard deadline(watchdog_, stop, std::chrono::duration<double>(options_.job_timeout_s));
  bool lease_lost = false, cancel_heard = false;
  // A stopped job ends cancelled (DELETE), released (shutdown) or failed (time limit).
  auto stopped = [&](const SolveStats& stats) {
    if (lease_lost) return;
    record.shots = stats.shots;
    record.unshot_fraction = stats.unshot_fraction;
    if (reason == StopReason::Shutdown && !cancel_heard) return store_.release(worker, record);
    if (deadline.timed_out() && !cancel_heard) {
      record.state = JobState::Failed;
      char limit[32];
      std::snprintf(limit, sizeof limit, "%g s", options_.job_timeout_s);
      record.error = std::string("the job ran past this server's time limit of ") + limit;
    } else {
      record.state = JobState::Cancelled;
    }
    store_.finish(worker, record, nullptr);
  };
  try {
    Scene scene = parse_scene(std::string_view(claim.scene_json), options_.files);
    const auto started = Clock::now();
    int last_shots = 0;
    double drafts_s = 0;  // inside the solve's wall time, reported apart
    auto last_step = started;
    // A step renews the lease; a step with a preview stores it and wakes the watchers.
    auto last_write = started;
    auto report = [&](const std::string& png) {
      if (png.empty() && seconds_since(last_write) < kProgressInterval) return;
      last_write = Clock::now();
      switch (store_.progress(worker, record, png)) {
        case Store::Lease::Held:
          metrics_.count_lease_renewal();
          break;
        case Store::Lease::CancelRequested:
          cancel_heard = true;
          stop.request_stop();
          break;
        case Store::Lease::Lost:
          lease_lost = true;
          stop.request_stop();
          std::fprintf(stderr, "job %s: its lease was lost; another worker may run it\n",
                       record.id.c_str());
          break;
      }
    };
    Scene draft = scene;
    draft.camera = draft_camera(scene.camera);
    Solution solution = solve(
        scene,
        [&](const Snapshot& snap, const Solution& partial) {
          metrics_.count_shots(snap.shots - last_shots, seconds_since(last_step));
          last_shots = snap.shots;
          if (snap.final) return true;
          record.shots = snap.shots;
          record.unshot_fraction = snap.unshot_fraction;
          record.elements = partial.mesh->elements.size();
          record.patches = partial.mesh->patches.size();
          std::string png;
          if (record.step == 0 ||
              record.seconds_previews < kPreviewShare * seconds_since(started)) {
            auto t = Clock::now();
            Image preview = render(draft, partial, snap, stop.get_token());
            if (stop.stop_requested()) return false;
            png = encode_image(preview, ImageFormat::Png, scene.camera.exposure);
            record.seconds_previews += seconds_since(t);
            drafts_s += seconds_since(t);
          }
          report(png);
          last_step = Clock::now();
          return !stop.stop_requested();
        },
        stop.get_token());
    if (stop.stop_requested()) return stopped(solution.stats);

    // The last step is the final image itself.
    auto t = Clock::now();
    Image image = render(scene, solution, stop.get_token());
    if (stop.stop_requested()) return stopped(solution.stats);
    Results results{encode_image(image, ImageFormat::Png, scene.camera.exposure),
                    encode_image(image, ImageFormat::Exr, 1),
                    encode_solution(claim.scene_json, solution)};
    record.shots = solution.stats.shots;
    record.unshot_fraction = solution.stats.unshot_fraction;
    record.seconds_previews += seconds_since(t);
    report(results.png);
    if (stop.stop_requested()) return stopped(solution.stats);
    record.state = JobState::Done;
    record.elements = solution.stats.elements;
    record.seconds_solve = solution.stats.seconds_solve - drafts_s;
    record.seconds_texture = solution.stats.seconds_texture;
    record.estimated_error = solution.stats.estimated_error;
    record.estimated_error_se = solution.stats.estimated_error_se;
    store_.finish(worker, record, &results);
  } catch (const std::exception& e) {
    if (lease_lost) return;
    record.state = JobState::Failed;
    record.error = e.what();
    store_.finish(worker, record, nullptr);
  }
}

}  // namespace bumprad
