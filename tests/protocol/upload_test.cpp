// Uploads to job requests: a bare .glb and a form become the one JSON job request, files in
// its scene's "files".
#include "protocol/upload.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "protocol/base64.h"
#include "protocol/json_parse.h"

namespace bumprad {
namespace {

using json = nlohmann::json;

std::string part(const std::string& name, const std::string& filename, const std::string& bytes) {
  return "--b\r\nContent-Disposition: form-data; name=\"" + name + "\"" +
         (filename.empty() ? "" : "; filename=\"" + filename + "\"") + "\r\n\r\n" + bytes + "\r\n";
}

TEST(Upload, JsonPassesAndAGlbIsTheSceneOfItsModel) {
  EXPECT_EQ(job_request_json("application/json; charset=utf-8", "{\"builtin\": \"cornell\"}"),
            "{\"builtin\": \"cornell\"}");
  EXPECT_EQ(job_request_json("", "{}"), "{}");
  const json glb = json::parse(job_request_json("model/gltf-binary", std::string("glTF\0\1", 6)));
  EXPECT_EQ(glb["scene"]["objects"][0]["file"], "model.glb");
  EXPECT_EQ(base64_decode(glb["scene"]["files"]["model.glb"].get<std::string>()),
            std::string("glTF\0\1", 6));
  EXPECT_THROW(job_request_json("text/plain", "x"), UnsupportedMediaType);
}

TEST(Upload, AFormsFilesJoinItsScene) {
  const std::string type = "multipart/form-data; boundary=b";
  const json job = json::parse(job_request_json(
      type, part("job", "", R"({"scene": {"objects": [], "files": {"a.png": "AA=="}},
                                "preview_every": 2})") +
                part("model", "room.glb", "GLB") + "--b--"));
  EXPECT_EQ(job["preview_every"], 2);
  EXPECT_EQ(job["scene"]["files"]["a.png"], "AA==");
  EXPECT_EQ(job["scene"]["files"]["room.glb"], base64_encode("GLB"));
  const json scene =
      json::parse(job_request_json(type, part("scene", "", R"({"objects": []})") + "--b--"));
  EXPECT_EQ(scene["scene"]["objects"], json::array());

  const auto error = [&](const std::string& body) {
    try {
      job_request_json(type, body + "--b--");
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error(part("model", "room.glb", "GLB")), "the form has no \"job\" or \"scene\" part");
  EXPECT_EQ(error(part("scene", "", "{}") + part("job", "", "{}")),
            "the form has more than one \"job\" or \"scene\" part");
  EXPECT_EQ(error(part("scene", "", "{}") + part("x", "", "1")),
            "form field \"x\" is neither \"job\", \"scene\" nor a file (a part with a filename)");
  EXPECT_EQ(error(part("job", "", R"({"builtin": "cornell"})") + part("f", "a.png", "")),
            "/scene: files come with an inline scene: the form's job has none");
  EXPECT_EQ(
      error(part("job", "", R"({"scene": {"files": {"a.png": ""}}})") + part("f", "a.png", "")),
      "/scene/files/a.png: is given twice: in the scene and as a file of the form");
  EXPECT_EQ(error(part("scene", "", "{") + part("f", "a.png", "")).find("/"), 0u);
  EXPECT_THROW(job_request_json(type, part("scene", "", "{")), MalformedBody);
}

}  // namespace
}  // namespace bumprad
