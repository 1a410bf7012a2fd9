#include "server/store.h"

#include <random>

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

void Store::check_queue(std::size_t waiting) const {
  if (waiting >= options().max_queue)
    throw QueueFull(std::to_string(waiting) + " jobs are already waiting (the limit)");
}

Store::Submitted Store::resubmitted(JobRecord earlier, std::string_view earlier_scene,
                                    std::string_view scene_json) {
  if (earlier_scene != scene_json) throw KeyReused("this Idempotency-Key was used for another job");
  return {std::move(earlier), false};
}

std::string redacted_url(std::string_view url) {
  const std::size_t scheme = url.find("://");
  const std::size_t start = scheme == std::string_view::npos ? 0 : scheme + 3;
  const std::size_t at = url.find('@', start);
  const std::size_t colon = url.find(':', start);
  if (at == std::string_view::npos || colon == std::string_view::npos || colon > at)
    return std::string(url);
  return std::string(url.substr(0, colon + 1)) + "***" + std::string(url.substr(at));
}

// Ids must not be guessable (they are the only key to a job), so they come from the
// system's entropy, not from a seeded stream.
std::string new_job_id() {
  static thread_local std::mt19937_64 random{std::random_device{}()};
  const char* hex = "0123456789abcdef";
  std::uint64_t bits = random();
  std::string id(16, '0');
  for (char& c : id) {
    c = hex[bits & 15];
    bits >>= 4;
  }
  return id;
}

bool is_valid_job_id(std::string_view id) {
  return id.size() == 16 && id.find_first_not_of("0123456789abcdef") == std::string_view::npos;
}

}  // namespace bumprad
