#include "server/job_queue.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "solver/camera.h"
#include "solver/image.h"
#include "solver/solution.h"
#include "solver/stopwatch.h"

namespace bumprad {
namespace {

constexpr double kPreviewShare = 0.25;

double unix_now() {
  using namespace std::chrono;
  return duration<double>(system_clock::now().time_since_epoch()).count();
}

void log_state(const JobRecord& j) {
  std::fprintf(stderr, "job %s %s (%s, %d/%d shots)%s%s\n", j.id.c_str(),
               std::string(to_string(j.state)).c_str(), j.scene_name.c_str(), j.shots, j.max_shots,
               j.error.empty() ? "" : ": ", j.error.c_str());
}

}  // namespace

JobQueue::JobQueue(JobStore& store, Metrics& metrics, Watchdog& watchdog, QueueOptions options)
    : store_(store), metrics_(metrics), watchdog_(watchdog), options_(std::move(options)) {
  std::vector<JobStore::Stored> stored = store_.load_all();
  std::sort(stored.begin(), stored.end(),
            [](const auto& a, const auto& b) { return a.record.created < b.record.created; });
  // A record that cannot be rewritten now (a full disk) is corrected in memory, and again
  // at the next start: the server starts all the same.
  auto correct = [&](const JobRecord& r) {
    try {
      store_.save_record(r);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "job %s: %s\n", r.id.c_str(), e.what());
    }
    log_state(r);
  };
  for (auto& s : stored) {
    JobRecord& r = s.record;
    if (r.state == JobState::Running) {
      r.state = JobState::Interrupted;
      r.finished = unix_now();
      r.error = "the server stopped while this job was running; submit it again";
      correct(r);
    }
    if (r.state == JobState::Done &&
        !(std::filesystem::exists(store_.solution_path(r.id)) &&
          std::filesystem::exists(store_.image_path(r.id, ImageFormat::Png)))) {
      r.state = JobState::Failed;
      r.error = "the job's files were lost from the data directory";
      correct(r);
    }
    auto job = std::make_shared<Job>(r);
    jobs_[r.id] = job;
    if (r.state == JobState::Queued) {
      waiting_.push_back(job);
    } else {
      last_used_[r.id] = r.finished;
      bytes_[r.id] = store_.bytes_used(r.id);
    }
  }
  if (!stored.empty())
    std::fprintf(stderr, "loaded %zu jobs from the data directory (%zu queued)\n", stored.size(),
                 waiting_.size());
  enforce_retention();
  for (int i = 0; i < std::max(1, options_.workers); ++i) workers_.emplace_back([this] { work(); });
}

JobQueue::~JobQueue() {
  shutdown();
}

std::shared_ptr<Job> JobQueue::submit(const JobRequest& request) {
  JobRecord r;
  r.id = JobStore::new_id();
  r.scene_name = request.scene_name;
  r.created = unix_now();
  r.max_shots = request.scene.solver.max_shots;
  r.preview_every = request.scene.solver.preview_every;
  auto job = std::make_shared<Job>(r);
  {
    std::lock_guard lock(mutex_);
    if (stopping_) throw QueueFull("the server is shutting down");
    if (waiting_.size() >= options_.max_queue)
      throw QueueFull(std::to_string(waiting_.size()) + " jobs are already waiting (the limit)");
    store_.create(r, request.scene_json);
    jobs_[r.id] = job;
    waiting_.push_back(job);
  }
  log_state(r);
  wake_.notify_one();
  return job;
}

std::shared_ptr<Job> JobQueue::find(const std::string& id) {
  std::lock_guard lock(mutex_);
  auto it = jobs_.find(id);
  if (it == jobs_.end()) return nullptr;
  if (last_used_.count(id)) last_used_[id] = unix_now();
  return it->second;
}

std::vector<JobRecord> JobQueue::list() const {
  std::vector<JobRecord> out;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, job] : jobs_) out.push_back(job->record());
  }
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return a.created > b.created; });
  return out;
}

JobQueue::Removal JobQueue::cancel_or_delete(const std::string& id) {
  std::shared_ptr<Job> job;
  {
    std::lock_guard lock(mutex_);
    auto it = jobs_.find(id);
    if (it == jobs_.end()) return Removal::Unknown;
    job = it->second;
    if (!is_finished(job->record().state)) {
      auto w = std::find(waiting_.begin(), waiting_.end(), job);
      if (w == waiting_.end()) {
        job->stop().request_stop();  // running: the worker records it as cancelled
        return Removal::Cancelled;
      }
      waiting_.erase(w);
    } else {
      forget(id);
    }
  }
  if (!is_finished(job->record().state)) {
    finish(job, [](JobRecord& r) { r.state = JobState::Cancelled; });
    return Removal::Cancelled;
  }
  store_.remove(id);
  std::fprintf(stderr, "job %s deleted\n", id.c_str());
  return Removal::Deleted;
}

std::shared_ptr<const LoadedSolution> JobQueue::solution(const std::string& id) {
  {
    std::lock_guard lock(mutex_);
    auto it = jobs_.find(id);
    if (it == jobs_.end() || it->second->record().state != JobState::Done) return nullptr;
    last_used_[id] = unix_now();
    for (auto c = cache_.begin(); c != cache_.end(); ++c)
      if (c->first == id) {
        cache_.splice(cache_.begin(), cache_, c);
        return c->second;
      }
  }
  auto loaded = std::make_shared<const LoadedSolution>(
      load_solution(store_.solution_path(id), options_.files));
  std::lock_guard lock(mutex_);
  remember(id, loaded);
  return loaded;
}

void JobQueue::remember(const std::string& id, std::shared_ptr<const LoadedSolution> solution) {
  cache_.remove_if([&](const auto& c) { return c.first == id; });  // loaded twice at once
  cache_.emplace_front(id, std::move(solution));
  if (cache_.size() > options_.cached_solutions) cache_.pop_back();
}

void JobQueue::forget(const std::string& id) {
  jobs_.erase(id);
  last_used_.erase(id);
  bytes_.erase(id);
  cache_.remove_if([&](const auto& c) { return c.first == id; });
}

Metrics::Gauges JobQueue::gauges() const {
  Metrics::Gauges g;
  std::lock_guard lock(mutex_);
  for (const auto& [id, job] : jobs_) ++g.jobs_by_state[std::size_t(job->record().state)];
  g.queue_depth = waiting_.size();
  g.queue_capacity = options_.max_queue;
  g.workers = workers_.size();
  return g;
}

void JobQueue::shutdown() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && workers_.empty()) return;
    stopping_ = true;
    for (auto& [id, job] : jobs_)
      if (job->record().state == JobState::Running) job->stop().request_stop();
  }
  wake_.notify_all();
  for (auto& w : workers_) w.join();
  workers_.clear();
}

void JobQueue::work() {
  for (;;) {
    std::shared_ptr<Job> job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || !waiting_.empty(); });
      if (stopping_) return;
      job = waiting_.front();
      waiting_.pop_front();
      job->update([](JobRecord& r) {
        r.state = JobState::Running;
        r.started = unix_now();
      });
    }
    run(job);
  }
}

void JobQueue::run(const std::shared_ptr<Job>& job) {
  const std::string id = job->record().id;
  Watchdog::Guard deadline(watchdog_, job->stop(),
                           std::chrono::duration<double>(options_.job_timeout_s));
  // A stopped job ends cancelled (DELETE), interrupted (shutdown) or failed (time limit).
  auto stopped = [&](const SolveStats& stats) {
    bool shutting_down;
    {
      std::lock_guard lock(mutex_);
      shutting_down = stopping_;
    }
    finish(job, [&](JobRecord& r) {
      r.shots = stats.shots;
      r.unshot_fraction = stats.unshot_fraction;
      if (shutting_down) {
        r.state = JobState::Interrupted;
        r.error = "the server shut down while this job was running";
      } else if (deadline.timed_out()) {
        r.state = JobState::Failed;
        char limit[32];
        std::snprintf(limit, sizeof limit, "%g s", options_.job_timeout_s);
        r.error = std::string("the job ran past this server's time limit of ") + limit;
      } else {
        r.state = JobState::Cancelled;
      }
    });
  };
  try {
    store_.save_record(job->record());
    log_state(job->record());
    auto scene_json = JobStore::read(store_.scene_path(id));
    if (!scene_json) throw std::runtime_error("the job's scene file is missing");
    Scene scene = parse_scene(std::string_view(*scene_json), options_.files);

    // Refinement steps become previews, kept on disk (the newest keep_steps) and handed to
    // the job's watchers. The last step is the final image itself, below.
    const auto started = Clock::now();
    int last_shots = 0;
    double drafts_s = 0;  // inside the solve's wall time, reported apart
    auto last_step = started;
    auto png_of = [&](const Image& image) {
      return std::make_shared<const std::string>(
          encode_image(image, ImageFormat::Png, scene.camera.exposure));
    };
    auto publish = [&](std::shared_ptr<const std::string> png, int shots, double unshot,
                       Clock::time_point t) {
      JobRecord r = job->record();
      int step = r.step + 1;
      store_.save_step(id, step, *png);
      int first = std::max(1, step - options_.keep_steps + 1);
      for (int s = std::max(1, r.first_kept_step); s < first; ++s) store_.drop_step(id, s);
      job->publish_step(png, [&](JobRecord& rec) {
        rec.step = step;
        rec.first_kept_step = first;
        rec.shots = shots;
        rec.unshot_fraction = unshot;
        rec.seconds_previews += seconds_since(t);
      });
    };
    // Previews are drafts (draft_camera) and take at most kPreviewShare of the job's
    // time: a step that comes sooner shows in the next preview.
    Scene draft = scene;
    draft.camera = draft_camera(scene.camera);
    Solution solution = solve(
        scene,
        [&](const Snapshot& snap, const Solution& partial) {
          metrics_.count_shots(snap.shots - last_shots, seconds_since(last_step));
          last_shots = snap.shots;
          if (snap.final) return true;
          JobRecord progress;
          job->update([&](JobRecord& r) {
            r.shots = snap.shots;
            r.unshot_fraction = snap.unshot_fraction;
            r.elements = partial.mesh->elements.size();
            r.patches = partial.mesh->patches.size();
            progress = r;
          });
          if (progress.step == 0 ||
              progress.seconds_previews < kPreviewShare * seconds_since(started)) {
            auto t = Clock::now();
            Image preview = render(draft, partial, snap, job->stop().get_token());
            if (job->stop().stop_requested()) return false;
            publish(png_of(preview), snap.shots, snap.unshot_fraction, t);
            drafts_s += seconds_since(t);
          }
          last_step = Clock::now();
          return true;
        },
        job->stop().get_token());

    if (job->stop().stop_requested()) return stopped(solution.stats);

    auto t = Clock::now();
    Image image = render(scene, solution, job->stop().get_token());
    if (job->stop().stop_requested()) return stopped(solution.stats);
    auto png = png_of(image);
    store_.save_file(store_.image_path(id, ImageFormat::Png), *png);
    store_.save_file(store_.image_path(id, ImageFormat::Exr),
                     encode_image(image, ImageFormat::Exr, 1));
    store_.save_file(store_.solution_path(id), encode_solution(*scene_json, solution));
    publish(png, solution.stats.shots, solution.stats.unshot_fraction, t);
    const SolveStats stats = solution.stats;
    auto loaded = std::make_shared<LoadedSolution>();
    loaded->scene = scene;
    loaded->scene_json = *scene_json;
    loaded->solution = std::move(solution);
    {
      std::lock_guard lock(mutex_);
      remember(id, std::move(loaded));
    }
    finish(job, [&](JobRecord& r) {
      r.state = JobState::Done;
      r.shots = stats.shots;
      r.unshot_fraction = stats.unshot_fraction;
      r.elements = stats.elements;
      r.seconds_solve = stats.seconds_solve - drafts_s;
      r.seconds_texture = stats.seconds_texture;
    });
  } catch (const std::exception& e) {
    finish(job, [&](JobRecord& r) {
      r.state = JobState::Failed;
      r.error = e.what();
    });
  }
}

void JobQueue::finish(const std::shared_ptr<Job>& job,
                      const std::function<void(JobRecord&)>& change) {
  JobRecord r = job->record();
  change(r);
  r.finished = unix_now();
  try {
    store_.save_record(r);  // last: the job is whole on disk before it says so
  } catch (const std::exception& e) {
    r.state = JobState::Failed;
    r.error = std::string("cannot write the job's record: ") + e.what();
  }
  job->update([&](JobRecord& rec) { rec = r; });
  log_state(r);
  const std::uintmax_t bytes = store_.bytes_used(r.id);  // disk I/O outside the lock
  {
    std::lock_guard lock(mutex_);
    last_used_[r.id] = r.finished;
    bytes_[r.id] = bytes;
  }
  enforce_retention();
}

void JobQueue::enforce_retention() {
  std::vector<std::string> evict;
  {
    std::lock_guard lock(mutex_);
    std::vector<std::pair<double, std::string>> by_use;
    std::uintmax_t total = 0;
    for (const auto& [id, used] : last_used_) {
      by_use.emplace_back(used, id);
      total += bytes_[id];
    }
    std::sort(by_use.begin(), by_use.end());
    std::size_t count = by_use.size();
    for (const auto& [used, id] : by_use) {
      if (count <= options_.max_jobs && total <= options_.max_bytes) break;
      evict.push_back(id);
      --count;
      total -= bytes_[id];
      forget(id);
    }
  }
  for (const std::string& id : evict) {
    store_.remove(id);
    std::fprintf(stderr, "job %s evicted (retention limits)\n", id.c_str());
  }
}

}  // namespace bumprad
