// The progress line `bumprad-client submit --watch` redraws on a terminal:
//   [##########----------]  50%  300/600 shots  unshot 12.34%  step 5  3.2 s
#pragma once

#include <string>

namespace bumprad {

// `width` is the bar's inside in characters; shots beyond max_shots show as full.
std::string progress_line(int shots, int max_shots, double unshot_fraction, int step,
                          double seconds, int width = 30);

}  // namespace bumprad
