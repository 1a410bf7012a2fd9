// `bumprad render SCENE -o OUT.(png|exr) [options]`: solve a scene and write its image.
#pragma once

#include <span>
#include <string_view>

namespace bumprad {

// Returns the process exit code: 0 done, 1 failed, 2 bad usage.
int render_command(std::span<const std::string_view> args);

}  // namespace bumprad
