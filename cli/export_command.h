// `bumprad export SOLUTION -o SCENE.glb`: a saved solution as a lit glTF binary (docs/export.md).
#pragma once

#include <span>
#include <string_view>

namespace bumprad {

// Returns the process exit code: 0 done, 1 failed, 2 bad usage.
int export_command(std::span<const std::string_view> args);

}  // namespace bumprad
