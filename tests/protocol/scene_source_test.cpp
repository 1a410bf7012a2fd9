// Where command-line scenes come from: built-in names, files on disk, bump files; every
// failure names the source and what is wrong.
#include "protocol/scene_source.h"

#include <gtest/gtest.h>

#include "protocol/builtin_scenes.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(SceneSource, BuiltinsAndFilesGiveTheSameScene) {
  std::string text;
  const Scene cornell = load_scene("builtin:cornell", &text);
  EXPECT_EQ(text, std::string(*find_builtin_scene("cornell")));
  const auto dir = test::fresh_temp_dir("scene-source");
  test::write_file(dir / "cornell.json", text);
  const Scene from_file = load_scene((dir / "cornell.json").string());
  EXPECT_EQ(from_file.objects.size(), cornell.objects.size());
  EXPECT_EQ(load_scene_text((dir / "cornell.json").string()), text);
}

TEST(SceneSource, FailuresNameTheSource) {
  EXPECT_NE(
      error_of([] { load_scene("builtin:nowhere"); }).find("unknown built-in scene \"nowhere\""),
      std::string::npos);
  EXPECT_NE(error_of([] { load_scene("/no/such/scene.json"); }).find("/no/such/scene.json"),
            std::string::npos);
  const auto dir = test::fresh_temp_dir("scene-source-bad");
  test::write_file(dir / "bad.json", R"({"objects": []})");
  const std::string bad = error_of([&] { load_scene((dir / "bad.json").string()); });
  EXPECT_NE(bad.find("bad.json"), std::string::npos) << bad;
  EXPECT_NE(bad.find("/objects: must have between 1 and"), std::string::npos) << bad;
}

TEST(SceneSource, BumpFilesReplaceBumpFunctionsByName) {
  Scene scene = load_scene("builtin:wrinkled-box");
  const auto dir = test::fresh_temp_dir("scene-source-bump");
  test::write_file(dir / "flat.json", R"({"wrinkles": {"type": "cylinder", "amplitude": 0.02}})");
  apply_bump_file((dir / "flat.json").string(), scene);
  test::write_file(dir / "other.json", R"({"bricks": {"type": "flat"}})");
  const std::string e = error_of([&] { apply_bump_file((dir / "other.json").string(), scene); });
  EXPECT_NE(e.find("/bricks: the scene has no bump function of this name"), std::string::npos) << e;
}

}  // namespace
}  // namespace bumprad
