// bumprad-client against the real server: submit --watch saves every preview and the final
// image, then image, retexture, status, list, solution (which bumprad retexture reads) and
// cancel; failures say what went wrong.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "solver/util/image.h"
#include "tests/test_command.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

class BumpradClient : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::fresh_temp_dir("client");
    server_ = std::make_unique<test::ServerProcess>(dir_ / "data");
  }
  test::CommandResult client(const std::string& args) const {
    return test::run_command(std::string(BUMPRAD_CLIENT_BIN) + " --server http://127.0.0.1:" +
                             std::to_string(server_->port()) + " " + args);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
  }

  fs::path dir_;
  std::unique_ptr<test::ServerProcess> server_;
};

TEST_F(BumpradClient, SubmitWatchImageRetextureCancel) {
  write("scene.json", test::small_scene_json(30));
  auto submitted = client("submit " + path("scene.json") + " --preview-every 10 --watch --out " +
                          path("previews"));
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
  std::string id = submitted.output.substr(0, submitted.output.find('\n'));
  ASSERT_EQ(id.size(), 16u) << submitted.output;
  for (int step = 1; step <= 3; ++step)
    EXPECT_TRUE(fs::exists(dir_ / "previews" / (id + "-step-" + std::to_string(step) + ".png")))
        << submitted.output;
  ASSERT_TRUE(fs::exists(dir_ / "previews" / (id + ".png")));
  EXPECT_EQ(read_image(dir_ / "previews" / (id + ".png")).width, 64);

  auto exr = client("image " + id + " -o " + path("final.exr"));
  EXPECT_EQ(exr.exit_code, 0) << exr.output;
  EXPECT_EQ(read_image(path("final.exr")).height, 48);

  write("bricks.json", R"({"wrinkles": {"type": "bricks", "amplitude": 0.02}})");
  auto re = client("retexture " + id + " --bump " + path("bricks.json") + " -o " + path("b.png"));
  EXPECT_EQ(re.exit_code, 0) << re.output;
  EXPECT_EQ(read_image(path("b.png")).width, 64);

  write("bad.json", R"({"wrinkles": {"type": "bricks", "mortar": 2}})");
  auto bad = client("retexture " + id + " --bump " + path("bad.json") + " -o " + path("x.png"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("(422): /bumps/wrinkles/mortar"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(path("x.png")));

  auto status = client("status " + id);
  EXPECT_EQ(json::parse(status.output)["state"], "done");
  auto list = client("list");
  EXPECT_EQ(list.exit_code, 0) << list.output;
  EXPECT_NE(list.output.find(id + "  done"), std::string::npos) << list.output;
  auto solution = client("solution " + id + " -o " + path("solution.json"));
  EXPECT_EQ(solution.exit_code, 0) << solution.output;
  auto local = test::run_command(std::string(BUMPRAD_BIN) + " retexture " + path("solution.json") +
                                 " -o " + path("local.png"));
  EXPECT_EQ(local.exit_code, 0) << local.output;
  EXPECT_EQ(read_image(path("local.png")).width, 64);
  auto deleted = client("cancel " + id);
  EXPECT_EQ(deleted.output, "deleted\n");
  auto gone = client("status " + id);
  EXPECT_EQ(gone.exit_code, 1);
  EXPECT_NE(gone.output.find("Not found (404)"), std::string::npos) << gone.output;
}

// A job's warnings are printed when it ends: a box turned inside out, seen from outside.
TEST_F(BumpradClient, WatchPrintsTheJobsWarnings) {
  write("inside-out.json", R"({
    "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "width": 32, "height": 24},
    "materials": {"m": {"reflectance": 0.5}, "lamp": {"reflectance": 0, "emission": 5}},
    "objects": [
      {"type": "box", "name": "crate", "material": "m", "center": [0, 0, 0], "size": [1, 1, 1],
       "flip_normals": true},
      {"type": "quad", "material": "lamp",
       "vertices": [[-1, 2, -1], [1, 2, -1], [1, 2, 1], [-1, 2, 1]]}],
    "solver": {"max_shots": 5}})");
  auto r = client("submit " + path("inside-out.json") + " --watch --out " + path("w"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(": warning: object \"crate\": "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("% of the image shows its back faces"), std::string::npos) << r.output;
}

// On a terminal (a pseudo-terminal from script(1)) --watch redraws one progress line.
TEST_F(BumpradClient, WatchDrawsAProgressBarOnATerminal) {
  write("scene.json", test::small_scene_json(30));
  const std::string command = std::string(BUMPRAD_CLIENT_BIN) +
                              " --server http://127.0.0.1:" + std::to_string(server_->port()) +
                              " submit " + path("scene.json") +
                              " --preview-every 10 --watch --out " + path("previews");
  auto watched = test::run_command("script -qec '" + command + "' /dev/null");
  ASSERT_EQ(watched.exit_code, 0) << watched.output;
  EXPECT_NE(watched.output.find("\r[###"), std::string::npos) << watched.output;
  EXPECT_NE(watched.output.find("] 100%  30/30 shots"), std::string::npos) << watched.output;
  EXPECT_EQ(watched.output.find("step 1: "), std::string::npos) << "no line per step";
  EXPECT_NE(watched.output.find("done -> "), std::string::npos) << watched.output;
}

TEST_F(BumpradClient, CancelARunningJob) {
  write("endless.json", test::small_scene_json(0, /*endless=*/true));
  auto submitted = client("submit " + path("endless.json"));
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
  std::string id = submitted.output.substr(0, 16);
  test::wait_for_job(server_->client(), id, {"running"});
  auto cancel = client("cancel " + id);
  EXPECT_EQ(cancel.exit_code, 0);
  EXPECT_NE(cancel.output.find("cancel"), std::string::npos);
  test::wait_for_job(server_->client(), id, {"cancelled"}, 10);
}

TEST_F(BumpradClient, FailuresSayWhatWentWrong) {
  auto refused = test::run_command(std::string(BUMPRAD_CLIENT_BIN) +
                                   " --server http://127.0.0.1:1 status 0123456789abcdef");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.output.find("cannot connect to http://127.0.0.1:1: Connection refused"),
            std::string::npos)
      << refused.output;
  auto unknown = client("submit builtin:attic");
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_NE(unknown.output.find("Invalid request (422): /builtin: unknown built-in scene"),
            std::string::npos)
      << unknown.output;
  write("broken.json", "{\"camera\": ");
  auto broken = client("submit " + path("broken.json"));
  EXPECT_EQ(broken.exit_code, 1);
  EXPECT_NE(broken.output.find("the scene: malformed JSON"), std::string::npos) << broken.output;
  auto usage = client("image 0123456789abcdef -o out.tiff");
  EXPECT_EQ(usage.exit_code, 2);
  EXPECT_NE(usage.output.find("must end in .png, .exr or .jpg"), std::string::npos);
  auto jpeg = client("image 0123456789abcdef -o out.jpg");
  EXPECT_EQ(jpeg.exit_code, 2);
  EXPECT_NE(jpeg.output.find("kept as PNG and EXR"), std::string::npos) << jpeg.output;
}

}  // namespace
}  // namespace bumprad
