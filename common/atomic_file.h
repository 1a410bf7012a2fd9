// Files appear whole or not at all: each is written beside its target under a temporary
// name, flushed to disk, then renamed over the target.
#pragma once

#include <filesystem>
#include <functional>
#include <string_view>

namespace bumprad {

// Calls write(temporary_path) and renames the result onto `target`. The temporary path
// keeps the target's extension (image writers choose the format by it). On any exception
// the temporary file is removed and the target is left as it was.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write);

void write_file_atomically(const std::filesystem::path& target, std::string_view contents);

}  // namespace bumprad
