// A command line that cannot be run as given: the command prints it with its usage and
// exits 2.
#pragma once

#include <stdexcept>

namespace bumprad {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace bumprad
