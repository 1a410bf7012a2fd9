// The solution export: one entry per element with its object, area and solved radiosity as
// the solve left them, and the solve's statistics.
#include "protocol/solution_json.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "protocol/scene_source.h"
#include "solver/solution.h"

namespace bumprad {
namespace {

TEST(SolutionJson, EveryElementWithItsRadiosityAndTheStats) {
  Scene scene = load_scene("builtin:cornell");
  scene.solver.max_shots = 40;
  const Solution solution = solve(scene);
  const auto j = nlohmann::json::parse(
      solution_to_json(scene, *solution.mesh, solution.radiosity, solution.stats));
  ASSERT_EQ(j["elements"].size(), solution.mesh->elements.size());
  for (std::size_t i = 0; i < solution.mesh->elements.size(); i += 97) {
    const auto& e = j["elements"][i];
    EXPECT_EQ(e["id"], i);
    EXPECT_EQ(e["object"], scene.objects[solution.mesh->elements[i].object].name);
    EXPECT_DOUBLE_EQ(e["area"].get<double>(), solution.mesh->elements[i].area);
    for (int c = 0; c < 3; ++c)
      EXPECT_DOUBLE_EQ(e["radiosity"][std::size_t(c)].get<double>(), solution.radiosity[i][c]);
  }
  EXPECT_EQ(j["stats"]["shots"], 40);
  EXPECT_EQ(j["stats"]["elements"], solution.mesh->elements.size());
}

}  // namespace
}  // namespace bumprad
