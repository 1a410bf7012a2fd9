// Where a command-line scene comes from: "builtin:NAME" or a JSON file on disk.
#pragma once

#include <string>

#include "solver/scene.h"

namespace bumprad {

// Throws std::runtime_error (unknown built-in, unreadable file) or SceneError (invalid).
Scene load_scene(const std::string& source);

}  // namespace bumprad
