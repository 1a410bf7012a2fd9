// Work spread over the machine's cores: the renderers' rows and pixels.
#pragma once

#include <functional>
#include <stop_token>

namespace bumprad {

// Runs work(i) for every i in [0, count), each index once, on every core (the calling
// thread among them); indices are handed out in order, so results that depend only on i do
// not depend on the threads. `stop` ends it before the next index.
void parallel_for(int count, const std::function<void(int)>& work, std::stop_token stop = {});

}  // namespace bumprad
