// A scene's own files: "files" maps names ("room.glb", "room/wall.png") to their bytes in
// base64, so a scene JSON, a stored job and a saved solution carry the models and images
// they name. While a scene is parsed they lie in a private temporary directory, which goes
// when the parse is done (everything is read at parse time).
#pragma once

#include <filesystem>
#include <set>
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace bumprad {

class EmbeddedFiles {
 public:
  // Checks every name (a relative path of plain parts: no "..", no absolute path) and its
  // base64, then writes the files. Throws SceneError naming the entry.
  // `pointer` is where `files` sits in the scene ("/files").
  EmbeddedFiles(const nlohmann::json& files, const std::string& pointer);
  ~EmbeddedFiles();
  EmbeddedFiles(const EmbeddedFiles&) = delete;
  EmbeddedFiles& operator=(const EmbeddedFiles&) = delete;

  bool contains(const std::string& name) const { return names_.count(name) > 0; }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::set<std::string> names_;
};

}  // namespace bumprad
