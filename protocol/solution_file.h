// The solution file (`bumprad render --save-map`, `bumprad retexture`): a solved scene with
// its perturbed radiosity map, to re-texture later without solving. Binary, versioned and
// checksummed; written atomically. Layout in docs/solution-file.md.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "protocol/scene_json.h"
#include "solver/scene/scene.h"
#include "solver/solution.h"

namespace bumprad {

class SolutionFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// `scene_json` is the scene's text as parsed (the mesh is rebuilt from it on load).
void save_solution(const std::filesystem::path& path, std::string_view scene_json,
                   const Solution& solution);
// The file's bytes, for a caller that writes them itself.
std::string encode_solution(std::string_view scene_json, const Solution& solution);

struct LoadedSolution {
  Scene scene;
  std::string scene_json;
  Solution solution;
};

// Throws SolutionFileError naming the file and what is wrong with it: not a solution
// file, another format version, truncated or corrupt, or inconsistent with its scene.
// The scene's image files are read as `files` allows.
LoadedSolution load_solution(const std::filesystem::path& path, const ImageFiles& files = {});
// The same from the file's bytes (a database column); `name` stands for the file in errors.
LoadedSolution decode_solution(std::string_view bytes, const std::string& name,
                               const ImageFiles& files = {});

}  // namespace bumprad
