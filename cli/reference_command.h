// `bumprad reference SCENE -o REF.exr --spp N [--seed S] [--bump B.json]`: the scene's
// ground truth by path tracing (solver/render/path_tracer.h), to measure bumprad's images against.
#pragma once

#include <span>
#include <string_view>

namespace bumprad {

// Returns the process exit code: 0 done, 1 failed, 2 bad usage.
int reference_command(std::span<const std::string_view> args);

}  // namespace bumprad
