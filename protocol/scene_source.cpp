#include "protocol/scene_source.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "protocol/builtin_scenes.h"
#include "protocol/scene_json.h"

namespace bumprad {

Scene load_scene(const std::string& source) {
  const std::string prefix = "builtin:";
  if (source.rfind(prefix, 0) == 0) {
    std::string name = source.substr(prefix.size());
    auto json = find_builtin_scene(name);
    if (!json)
      throw std::runtime_error("unknown built-in scene \"" + name +
                               "\" (`bumprad scenes` lists them)");
    return parse_scene(*json);
  }
  std::ifstream in(source, std::ios::binary);
  if (!in) throw std::runtime_error(source + ": cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  try {
    return parse_scene(text.str());
  } catch (const SceneError& e) {
    throw std::runtime_error(source + ": " + e.what());
  }
}

}  // namespace bumprad
