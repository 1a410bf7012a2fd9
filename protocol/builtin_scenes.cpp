#include "protocol/builtin_scenes.h"

namespace bumprad {

std::optional<std::string_view> find_builtin_scene(std::string_view name) {
  for (const BuiltinScene& s : builtin_scenes())
    if (s.name == name) return s.json;
  return std::nullopt;
}

}  // namespace bumprad
