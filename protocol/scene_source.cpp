#include "protocol/scene_source.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "protocol/builtin_scenes.h"
#include "protocol/model_import.h"
#include "protocol/scene_json.h"

#include <nlohmann/json.hpp>

namespace bumprad {

std::string load_scene_text(const std::string& source) {
  const std::string prefix = "builtin:";
  if (source.rfind(prefix, 0) == 0) {
    std::string name = source.substr(prefix.size());
    auto json = find_builtin_scene(name);
    if (!json)
      throw std::runtime_error("unknown built-in scene \"" + name +
                               "\" (`bumprad scenes` lists them)");
    return std::string(*json);
  }
  std::ifstream in(source, std::ios::binary);
  if (!in) throw std::runtime_error(source + ": cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

Scene load_scene(const std::string& source, std::string* text_out) {
  // A model file is the scene of one placed model: its camera or one framed on it.
  const bool model = source.rfind("builtin:", 0) != 0 && is_model_file(source);
  const std::string text =
      model ? nlohmann::json{{"objects", {{{"type", "model"}, {"file", source}}}}}.dump()
            : load_scene_text(source);
  if (text_out) *text_out = text;
  try {
    std::vector<std::string> warnings;
    Scene scene = parse_scene(std::string_view(text), {}, &warnings);
    // A model file's warnings name it after the field that placed it: the field goes.
    for (const std::string& w : warnings)
      std::fprintf(stderr, "bumprad: warning: %s\n",
                   model ? w.substr(w.find(": ") + 2).c_str() : (source + ": " + w).c_str());
    return scene;
  } catch (const SceneError& e) {
    if (source.rfind("builtin:", 0) == 0) throw;
    // A model's errors name its file already, after the field that placed it.
    if (model && e.pointer() == "/objects/0/file") throw std::runtime_error(e.reason());
    throw std::runtime_error(source + ": " + e.what());
  }
}

void apply_bump_file(const std::string& path, Scene& scene) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open the bump file");
  try {
    apply_bump_overrides(nlohmann::json::parse(in), scene);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path + ": malformed JSON: " + e.what());
  } catch (const SceneError& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace bumprad
