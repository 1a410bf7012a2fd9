// Where a command-line scene comes from: "builtin:NAME", a JSON file on disk, or a model file
// (.glb, .gltf, .obj, .fbx and the rest Assimp reads; protocol/model_import.h).
#pragma once

#include <string>

#include "solver/scene/scene.h"

namespace bumprad {

// The JSON text of a scene source. Throws std::runtime_error (unknown built-in, unreadable).
std::string load_scene_text(const std::string& source);

// Throws std::runtime_error (unknown built-in, unreadable or invalid file). With `text`,
// also hands back the JSON it parsed (what a saved solution keeps): for a model file, the
// scene that places it, {"objects": [{"type": "model", "file": ...}]}. Models' warnings go
// to stderr.
Scene load_scene(const std::string& source, std::string* text = nullptr);

// Applies a bump file (the JSON of a scene's "bumps" block) to `scene`, replacing bump
// functions by name. Throws std::runtime_error naming the file and the field.
void apply_bump_file(const std::string& path, Scene& scene);

}  // namespace bumprad
