// `bumprad reference`: the path-traced ground truth from the command line, the same image
// for the same seed, and clear usage errors.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "solver/util/image.h"
#include "tests/test_command.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

test::CommandResult run(const std::string& args) {
  return test::run_command(std::string(BUMPRAD_BIN) + " reference " + args);
}

TEST(ReferenceCli, PathTracesTheSceneTheSameForTheSameSeed) {
  auto dir = test::fresh_temp_dir("reference");
  std::ofstream(dir / "room.json") << test::small_scene_json(10);
  const std::string scene = (dir / "room.json").string();
  auto a = run(scene + " --spp 4 --seed 3 -o " + (dir / "a.exr").string());
  ASSERT_EQ(a.exit_code, 0) << a.output;
  EXPECT_NE(a.output.find("4 samples a pixel, seed 3"), std::string::npos) << a.output;
  EXPECT_NE(a.output.find("bumprad reference: 100%"), std::string::npos) << a.output;
  Image image = read_image(dir / "a.exr");
  EXPECT_EQ(image.width, 64);
  double sum = 0;
  for (float v : image.rgb) {
    EXPECT_TRUE(std::isfinite(v));
    sum += v;
  }
  EXPECT_GT(sum, 0) << "the room is lit";
  ASSERT_EQ(run(scene + " --spp 4 --seed 3 -o " + (dir / "b.exr").string()).exit_code, 0);
  ASSERT_EQ(run(scene + " --spp 4 --seed 4 -o " + (dir / "c.exr").string()).exit_code, 0);
  // Pixels, not bytes: the EXR header carries the time it was written.
  EXPECT_EQ(read_image(dir / "b.exr").rgb, image.rgb);
  EXPECT_NE(read_image(dir / "c.exr").rgb, image.rgb);
}

TEST(ReferenceCli, UsageErrors) {
  auto r = run("builtin:cornell");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("no output image given"), std::string::npos) << r.output;
  r = run("builtin:cornell -o x.exr --spp lots");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--spp: \"lots\" is not a whole number"), std::string::npos) << r.output;
  r = run("builtin:cornell -o x.tiff");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("use .exr, .png or .jpg"), std::string::npos) << r.output;
  r = run("builtin:nowhere -o x.exr");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("unknown built-in scene"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace bumprad
