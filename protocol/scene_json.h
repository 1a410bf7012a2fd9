// The JSON scene format (docs/scene-format.md, protocol/scene.schema.json) to a validated
// Scene. Every rejection names the offending field as a JSON pointer and says why.
#pragma once

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
        pointer_(std::move(pointer)) {}
  // RFC 6901 pointer to the offending value; empty for the document itself.
  const std::string& pointer() const { return pointer_; }

 private:
  std::string pointer_;
};

// Throws SceneError; never returns a partly valid scene.
Scene parse_scene(std::string_view json_text);
Scene parse_scene(const nlohmann::json& document);

// Applies settings overrides given in JSON form ({"max_shots": 50}), with the same checks
// as a scene's "solver" block; `pointer` prefixes error locations.
void apply_solver_settings(const nlohmann::json& settings, SolverSettings& out,
                           const std::string& pointer = "/solver");

// Replaces the scene's bump functions by name with those in `bumps` (the same JSON as a
// scene's "bumps" block), e.g. to re-texture with `--bump FILE.json`. Names the scene does
// not have are refused; `pointer` prefixes error locations.
void apply_bump_overrides(const nlohmann::json& bumps, Scene& scene,
                          const std::string& pointer = "");

}  // namespace bumprad
