// The scenes that ship inside the binary, by name ("builtin:NAME" on the command line).
// Their source is scenes/NAME.json.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

namespace bumprad {

struct BuiltinScene {
  std::string_view name;
  std::string_view json;
};

const std::vector<BuiltinScene>& builtin_scenes();
std::optional<std::string_view> find_builtin_scene(std::string_view name);

}  // namespace bumprad
