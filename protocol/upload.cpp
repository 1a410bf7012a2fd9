#include "protocol/upload.h"

#include <cctype>

#include <nlohmann/json.hpp>

#include "protocol/base64.h"
#include "protocol/json_node.h"
#include "protocol/json_parse.h"

namespace bumprad {
namespace {

using json = nlohmann::json;

std::string media_type(std::string_view content_type) {
  std::string type(content_type.substr(0, content_type.find(';')));
  while (!type.empty() && type.back() == ' ') type.pop_back();
  for (char& c : type) c = char(std::tolower(static_cast<unsigned char>(c)));
  return type;
}

std::string from_form(std::string_view content_type, std::string_view body) {
  json request, files = json::object();
  bool have_request = false;
  for (const FormPart& part : parse_multipart(content_type, body)) {
    if (part.filename.empty() && (part.name == "job" || part.name == "scene")) {
      if (have_request) throw MalformedBody("the form has more than one \"job\" or \"scene\" part");
      have_request = true;
      json document = parse_json(part.body);
      request = part.name == "job" ? std::move(document) : json{{"scene", std::move(document)}};
    } else if (!part.filename.empty()) {
      if (files.contains(part.filename))
        throw MalformedBody("the form has two files named \"" + part.filename + "\"");
      files[part.filename] = base64_encode(part.body);
    } else {
      throw MalformedBody("form field \"" + part.name +
                          "\" is neither \"job\", \"scene\" nor a file (a part with a filename)");
    }
  }
  if (!have_request) throw MalformedBody("the form has no \"job\" or \"scene\" part");
  if (!files.empty()) {
    if (!request.is_object() || !request.contains("scene") || !request["scene"].is_object())
      throw SceneError("/scene", "files come with an inline scene: the form's job has none");
    json& scene = request["scene"];
    if (!scene.contains("files")) scene["files"] = json::object();
    if (!scene["files"].is_object()) throw SceneError("/scene/files", "must be an object");
    for (auto it = files.begin(); it != files.end(); ++it) {
      if (scene["files"].contains(it.key()))
        throw SceneError("/scene/files/" + escape_token(it.key()),
                         "is given twice: in the scene and as a file of the form");
      scene["files"][it.key()] = std::move(it.value());
    }
  }
  return request.dump();
}

}  // namespace

std::string job_request_json(std::string_view content_type, std::string_view body) {
  const std::string type = media_type(content_type);
  if (type.empty() || type == "application/json") return std::string(body);
  if (type == "model/gltf-binary")
    return json{{"scene",
                 {{"files", {{"model.glb", base64_encode(body)}}},
                  {"objects", {{{"type", "model"}, {"file", "model.glb"}}}}}}}
        .dump();
  if (type == "multipart/form-data") return from_form(content_type, body);
  throw UnsupportedMediaType(
      "a job is application/json, model/gltf-binary (a .glb) or "
      "multipart/form-data (the job or scene JSON and its files); got " +
      std::string(content_type));
}

}  // namespace bumprad
