// `bumprad retexture M --bump B.json -o OUT.(png|exr)`: a saved solution rendered with new
// bump functions, without solving again.
#pragma once

#include <span>
#include <string_view>

namespace bumprad {

// Returns the process exit code: 0 done, 1 failed, 2 bad usage.
int retexture_command(std::span<const std::string_view> args);

}  // namespace bumprad
