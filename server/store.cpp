#include "server/store.h"

namespace bumprad {

void Store::subscribe(std::function<void(const JobEvent&)> listener) {
  std::lock_guard lock(listeners_mutex_);
  listeners_.push_back(std::move(listener));
}

void Store::emit(const JobEvent& event) {
  std::vector<std::function<void(const JobEvent&)>> listeners;
  {
    std::lock_guard lock(listeners_mutex_);
    listeners = listeners_;
  }
  for (const auto& l : listeners) l(event);
}

}  // namespace bumprad
