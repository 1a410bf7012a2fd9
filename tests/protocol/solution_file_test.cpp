// Saved solutions round-trip bit for bit and render the same pixels; damaged, foreign and
// other-version files are refused with a clear message.
#include "protocol/solution_file.h"

#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "protocol/builtin_scenes.h"
#include "protocol/scene_json.h"
#include "tests/test_files.h"

namespace bumprad {
namespace {

namespace fs = std::filesystem;

class SolutionFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::fresh_temp_dir("solution-file");
    auto doc = nlohmann::json::parse(*find_builtin_scene("wrinkled-box"));
    doc["solver"]["max_shots"] = 30;
    doc["solver"]["hemicube_resolution"] = 64;
    doc["solver"]["tolerance"] = 0.5;  // met at once: one error estimate, kept in the file
    doc["camera"]["width"] = doc["camera"]["height"] = 96;
    text_ = doc.dump();
    scene_ = parse_scene(std::string_view(text_));
  }
  fs::path saved() {
    fs::path p = dir_ / "s.bumprad";
    solution_ = solve(scene_);
    save_solution(p, text_, solution_);
    return p;
  }
  std::string bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  void write(const fs::path& p, const std::string& b) { std::ofstream(p, std::ios::binary) << b; }
  void expect_refused(const fs::path& p, const std::string& reason) {
    try {
      load_solution(p);
      ADD_FAILURE() << "loaded; expected " << reason;
    } catch (const SolutionFileError& e) {
      EXPECT_NE(std::string(e.what()).find(p.string() + ": " + reason), std::string::npos)
          << e.what();
    }
  }

  fs::path dir_;
  std::string text_;
  Scene scene_;
  Solution solution_;
};

TEST_F(SolutionFile, RoundTripIsBitExact) {
  LoadedSolution back = load_solution(saved());
  EXPECT_EQ(back.scene_json, text_);
  EXPECT_EQ(back.solution.radiosity, solution_.radiosity);
  EXPECT_EQ(back.solution.display, solution_.display);
  EXPECT_FALSE(solution_.direct.empty());  // exact direct light, the default
  EXPECT_EQ(back.solution.direct, solution_.direct);
  ASSERT_TRUE(back.solution.map);
  ASSERT_EQ(back.solution.map->vertex_count(), solution_.map->vertex_count());
  for (std::uint32_t s = 0; s < solution_.map->vertex_count(); ++s) {
    auto a = solution_.map->values(s), b = back.solution.map->values(s);
    EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin())) << s;
  }
  EXPECT_EQ(back.solution.stats.shots, 30);
  EXPECT_GT(solution_.stats.estimated_error, 0);
  EXPECT_EQ(back.solution.stats.estimated_error, solution_.stats.estimated_error);
  EXPECT_EQ(back.solution.stats.estimated_error_se, solution_.stats.estimated_error_se);
  EXPECT_EQ(back.solution.stats.perturbed_elements, solution_.stats.perturbed_elements);
  EXPECT_EQ(render(back.scene, back.solution).rgb, render(scene_, solution_).rgb);
}

// The rays a pixel a tolerance chose (SolveStats::antialias) come back with the solution,
// and its images are rendered with them.
TEST_F(SolutionFile, TheRaysAPixelAToleranceChoseRoundTrip) {
  const fs::path p = saved();
  const Image camera_rays = render(scene_, solution_);
  solution_.stats.antialias = SolverSettings::kToleranceAntialias;
  save_solution(p, text_, solution_);
  LoadedSolution back = load_solution(p);
  EXPECT_EQ(back.solution.stats.antialias, SolverSettings::kToleranceAntialias);
  const Image image = render(back.scene, back.solution);
  EXPECT_EQ(image.rgb, render(scene_, solution_).rgb);
  EXPECT_NE(image.rgb, camera_rays.rgb);
}

// Adaptively refined meshes are not a function of the scene alone: the file keeps the
// splits, and loading rebuilds the same refined mesh.
TEST_F(SolutionFile, AdaptiveRefinementsRoundTrip) {
  auto doc = nlohmann::json::parse(text_);
  doc["solver"]["adaptive"] = {{"levels", 1}};
  text_ = doc.dump();
  scene_ = parse_scene(std::string_view(text_));
  LoadedSolution back = load_solution(saved());
  ASSERT_EQ(solution_.refinements.size(), 1u);
  EXPECT_GT(solution_.refinements[0].size(), 0u);
  EXPECT_EQ(back.solution.refinements, solution_.refinements);
  EXPECT_EQ(back.solution.mesh->elements.size(), solution_.mesh->elements.size());
  EXPECT_EQ(back.solution.radiosity, solution_.radiosity);
  EXPECT_EQ(render(back.scene, back.solution).rgb, render(scene_, solution_).rgb);
}

// Files before version 5 were written when the map stored sampled normals, whatever their
// scene says: a version-4 file (the bytes a solve with sampled normals writes, stamped 4,
// its checksum redone) loads as sampled normals and renders as before.
TEST_F(SolutionFile, AVersionFourFileKeepsItsSampledNormals) {
  Scene samples = scene_;
  samples.solver.map.basis = MapBasisKind::SampledNormals;
  solution_ = solve(samples);
  std::string b = encode_solution(text_, solution_);
  b.erase(b.size() - 8 - sizeof(std::int32_t), sizeof(std::int32_t));  // version 6's last field
  b[8] = 4;
  std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a 64, as docs/solution-file.md says
  for (std::size_t i = 0; i + 8 < b.size(); ++i) h = (h ^ std::uint8_t(b[i])) * 0x100000001b3ull;
  std::memcpy(b.data() + b.size() - 8, &h, 8);
  const fs::path p = dir_ / "v4.bumprad";
  write(p, b);
  LoadedSolution back = load_solution(p);
  EXPECT_EQ(back.solution.map->basis().size(), 17u);
  EXPECT_EQ(render(back.scene, back.solution).rgb, render(samples, solution_).rgb);
}

TEST_F(SolutionFile, RefusesDamagedForeignAndOtherVersionFiles) {
  fs::path p = saved();
  std::string good = bytes(p);
  fs::path bad = dir_ / "bad.bumprad";

  write(bad, good.substr(0, good.size() / 2));
  expect_refused(bad, "corrupt or truncated");
  write(bad, good.substr(0, 10));
  expect_refused(bad, "truncated");
  std::string flipped = good;
  flipped[good.size() / 3] ^= 0x20;
  write(bad, flipped);
  expect_refused(bad, "corrupt or truncated solution file (checksum mismatch)");
  std::string version = good;
  version[8] = 7;
  write(bad, version);
  expect_refused(bad, "solution file format version 7; this build reads versions 1 to 6");
  write(bad, "\x89PNG\r\n\x1a\n and then some");
  expect_refused(bad, "not a bumprad solution file");
  expect_refused(dir_ / "missing.bumprad", "cannot open");
}

}  // namespace
}  // namespace bumprad
