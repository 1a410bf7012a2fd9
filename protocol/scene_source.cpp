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
  if (source.rfind("builtin:", 0) != 0 && is_model_file(source)) {
    if (text_out) text_out->clear();
    const ImportedModel model = import_model(source);
    for (const std::string& w : model.warnings)
      std::fprintf(stderr, "bumprad: warning: %s\n", w.c_str());
    return scene_from_model(model);
  }
  std::string text = load_scene_text(source);
  if (text_out) *text_out = text;
  try {
    return parse_scene(std::string_view(text));
  } catch (const SceneError& e) {
    if (source.rfind("builtin:", 0) == 0) throw;
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
