#include "server/solution_cache.h"

namespace bumprad {
namespace {

// A view and the solution it looks at, which must outlive it: one allocation, handed out as
// the view alone.
struct HeldView {
  std::shared_ptr<const LoadedSolution> solved;
  Scene scene;
  SolutionView view;
  HeldView(std::shared_ptr<const LoadedSolution> s, Scene viewed)
      : solved(std::move(s)), scene(std::move(viewed)), view(scene, solved->solution) {}
};

}  // namespace

std::shared_ptr<const LoadedSolution> SolutionCache::get(const std::string& id) {
  {
    std::lock_guard lock(mutex_);
    for (auto e = entries_.begin(); e != entries_.end(); ++e)
      if (e->id == id) {
        entries_.splice(entries_.begin(), entries_, e);
        return e->solved;
      }
  }
  auto bytes = store_.read(id, Artifact::Solution);
  if (!bytes) return nullptr;
  auto loaded = std::make_shared<const LoadedSolution>(
      decode_solution(*bytes, "job " + id + "'s solution", files_));
  std::lock_guard lock(mutex_);
  entries_.remove_if([&](const Entry& e) { return e.id == id; });  // loaded twice at once
  entries_.push_front({id, loaded, {}});
  if (entries_.size() > capacity_) entries_.pop_back();
  return loaded;
}

std::shared_ptr<const SolutionView> SolutionCache::view(
    const std::string& id, const std::shared_ptr<const LoadedSolution>& solved,
    const Camera& camera) {
  auto find = [&]() -> std::shared_ptr<const SolutionView> {
    for (Entry& e : entries_) {
      if (e.id != id || e.solved != solved) continue;
      for (auto v = e.views.begin(); v != e.views.end(); ++v)
        if (same_view((*v)->camera(), camera)) {
          e.views.splice(e.views.begin(), e.views, v);
          return *v;
        }
    }
    return nullptr;
  };
  {
    std::lock_guard lock(mutex_);
    if (auto kept = find()) return kept;
  }
  Scene scene = solved->scene;
  scene.camera = camera;
  auto held = std::make_shared<const HeldView>(solved, std::move(scene));
  std::shared_ptr<const SolutionView> view(held, &held->view);
  std::lock_guard lock(mutex_);
  if (auto kept = find()) return kept;  // made twice at once: the first one serves
  for (Entry& e : entries_)
    if (e.id == id && e.solved == solved) {
      e.views.push_front(view);
      if (e.views.size() > kViewsPerJob) e.views.pop_back();
    }
  return view;
}

}  // namespace bumprad
