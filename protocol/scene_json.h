// The JSON scene format (docs/scene-format.md, protocol/scene.schema.json) to a validated
// Scene. Every rejection names the offending field as a JSON pointer and says why.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

#include "solver/scene.h"

namespace bumprad {

class SceneError : public std::runtime_error {
 public:
  SceneError(std::string pointer, const std::string& reason)
      : std::runtime_error((pointer.empty() ? std::string("/") : pointer) + ": " + reason),
        pointer_(std::move(pointer)),
        reason_(reason) {}
  // RFC 6901 pointer to the offending value; empty for the document itself.
  const std::string& pointer() const { return pointer_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string pointer_;
  std::string reason_;
};

// The text is not JSON at all (HTTP answers 400 for this, 422 for other SceneErrors).
class MalformedJson : public SceneError {
 public:
  explicit MalformedJson(const std::string& reason) : SceneError("", reason) {}
};

// Where a scene's image files (colour textures, height maps) may be read from. The command
// line reads them relative to the working directory. The server reads them only from its
// asset directory, or refuses them, so that a request can never name a server path.
struct ImageFiles {
  enum class Access { WorkingDirectory, Sandbox, Refused };
  Access access = Access::WorkingDirectory;
  std::filesystem::path root;  // the sandbox

  static ImageFiles sandbox(std::filesystem::path dir) { return {Access::Sandbox, std::move(dir)}; }
  static ImageFiles refused() { return {Access::Refused, {}}; }

  // The file to open for `name`; throws std::invalid_argument saying why it may not be.
  std::filesystem::path resolve(const std::string& name) const;
};

// Throws SceneError; never returns a partly valid scene.
Scene parse_scene(std::string_view json_text, const ImageFiles& files = {});
Scene parse_scene(const nlohmann::json& document, const ImageFiles& files = {});

// Arrays and objects nest at most this deep in any JSON bumprad reads (a scene needs 5, a
// request 6): deeper documents are refused while parsing, before anything copies them, since
// copying, printing and freeing a JSON value recurse once per level.
constexpr int kMaxJsonDepth = 32;

// JSON text to a document; throws MalformedJson saying where and why, also for nesting
// deeper than kMaxJsonDepth.
nlohmann::json parse_json(std::string_view text);

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
