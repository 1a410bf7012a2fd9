// The built-in scenes parse, mesh to the sizes their descriptions promise, and are the
// same text as the files under scenes/.
#include "protocol/builtin_scenes.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "protocol/scene_json.h"
#include "solver/scene/mesh.h"

namespace bumprad {
namespace {

TEST(BuiltinScenes, AllParseAndMatchTheirFiles) {
  ASSERT_EQ(builtin_scenes().size(), 3u);
  for (const BuiltinScene& b : builtin_scenes()) {
    std::ifstream in(std::string(BUMPRAD_SOURCE_DIR) + "/scenes/" + std::string(b.name) + ".json");
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_EQ(text.str(), b.json) << b.name;
    EXPECT_NO_THROW(parse_scene(b.json)) << b.name;
  }
  EXPECT_FALSE(find_builtin_scene("nope"));
}

TEST(BuiltinScenes, PaperRoomHasAboutThePapersElementCount) {
  Scene s = parse_scene(*find_builtin_scene("paper-room"));
  Mesh m = build_mesh(s);
  std::printf("paper-room: %zu elements, %zu patches\n", m.elements.size(), m.patches.size());
  // Chen & Wu's Fig. 7 room: 3,327 elements.
  EXPECT_GT(m.elements.size(), 3000u);
  EXPECT_LT(m.elements.size(), 3700u);
}

}  // namespace
}  // namespace bumprad
