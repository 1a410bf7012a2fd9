// Whether a file lies inside a directory once symbolic links are followed: the one test that
// keeps a server's asset files, and the textures its models name, inside their directory.
#pragma once

#include <filesystem>

namespace bumprad {

// True when `file` (existing or not) resolves to a path under `dir`.
bool lies_inside(const std::filesystem::path& dir, const std::filesystem::path& file);

}  // namespace bumprad
