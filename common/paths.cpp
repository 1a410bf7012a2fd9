#include "common/paths.h"

#include <algorithm>
#include <system_error>

namespace bumprad {

bool lies_inside(const std::filesystem::path& dir, const std::filesystem::path& file) {
  std::error_code error;
  const auto base = std::filesystem::weakly_canonical(dir, error);
  if (error) return false;
  const auto full = std::filesystem::weakly_canonical(file, error);
  if (error) return false;
  const auto [b, f] = std::mismatch(base.begin(), base.end(), full.begin(), full.end());
  return b == base.end();
}

}  // namespace bumprad
