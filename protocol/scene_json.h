// The JSON scene format (docs/scene-format.md, protocol/scene.schema.json) to a validated
// Scene. Every rejection names the offending field as a JSON pointer and says why.
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "protocol/embedded_files.h"
#include "protocol/json_parse.h"
#include "solver/scene/scene.h"

namespace bumprad {

// Where a scene's image files (colour textures, height maps) may be read from. The command
// line reads them relative to the working directory. The server reads them only from its
// asset directory, or refuses them, so that a request can never name a server path.
struct ImageFiles {
  enum class Access { WorkingDirectory, Sandbox, Refused };
  Access access = Access::WorkingDirectory;
  std::filesystem::path root;  // the sandbox
  // What one scene's images may take to decode in all (a server's --max-image-memory).
  std::size_t max_image_bytes = Limits::kMaxImageBytes;
  // Set while a scene is parsed: its own "files", which its names reach first, and the
  // budget its images draw from.
  const EmbeddedFiles* embedded = nullptr;
  ImageBudget* budget = nullptr;

  static ImageFiles sandbox(std::filesystem::path dir) { return {Access::Sandbox, std::move(dir)}; }
  static ImageFiles refused() { return {Access::Refused, {}}; }

  // The file to open for `name`; throws std::invalid_argument saying why it may not be.
  std::filesystem::path resolve(const std::string& name) const;
  // The directory whose files `name`'s may name in turn (a model's textures): the scene's
  // files' or the sandbox; none from the working directory.
  std::optional<std::filesystem::path> confinement(const std::string& name) const;
};

// Throws SceneError; never returns a partly valid scene. What a placed model's importer
// dropped or assumed goes to `warnings` (each names the object's field and its file).
Scene parse_scene(std::string_view json_text, const ImageFiles& files = {},
                  std::vector<std::string>* warnings = nullptr);
Scene parse_scene(const nlohmann::json& document, const ImageFiles& files = {},
                  std::vector<std::string>* warnings = nullptr);

// `base` with the keys of a camera block that `changes` gives, e.g. to re-render from a new
// view or at another size; with the same checks as a scene's "camera".
Camera parse_camera_changes(const nlohmann::json& changes, const Camera& base,
                            const std::string& pointer);

// Applies settings overrides given in JSON form ({"max_shots": 50}), with the same checks
// as a scene's "solver" block; `pointer` prefixes error locations.
void apply_solver_settings(const nlohmann::json& settings, SolverSettings& out,
                           const std::string& pointer = "/solver");

// Replaces the scene's bump functions by name with those in `bumps` (the same JSON as a
// scene's "bumps" block), e.g. to re-texture with `--bump FILE.json`. Names the scene does
// not have are refused; `pointer` prefixes error locations.
void apply_bump_overrides(const nlohmann::json& bumps, Scene& scene,
                          const std::string& pointer = "", const ImageFiles& files = {});

}  // namespace bumprad
