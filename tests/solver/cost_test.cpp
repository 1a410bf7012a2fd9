// The cost model that lets the server refuse work before it starts: the shots a solve is
// expected to take, each linear in the counts that drive its loops; close to what the
// built-in scenes take, and far above the budget for the requests that once held the server
// for hours.
#include "solver/cost.h"

#include <gtest/gtest.h>

#include "protocol/builtin_scenes.h"
#include "protocol/scene_json.h"
#include "solver/solution.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

Scene builtin(const char* name) {
  return parse_scene(*find_builtin_scene(name));
}

TEST(Cost, GrowsWithShotsElementsResolutionAndPixels) {
  Scene s = builtin("cornell");
  s.solver.max_shots = 100;  // below the shots it expects: the cap counts
  const CostEstimate base = estimate_cost(s);
  EXPECT_GT(base.solve_s, 0);
  EXPECT_GT(base.render_s, 0);
  Scene more = s;
  more.solver.max_shots *= 2;
  const CostEstimate doubled = estimate_cost(more);
  EXPECT_EQ(doubled.setup_s, base.setup_s);
  // Twice the shots, nearly twice the time: the emitters' first shots (their near field)
  // stay as they were.
  EXPECT_NEAR(doubled.solve_s - doubled.setup_s, 2 * (base.solve_s - base.setup_s),
              0.02 * (base.solve_s - base.setup_s));
  more = s;
  more.solver.hemicube_resolution *= 4;
  EXPECT_GT(estimate_cost(more).solve_s, base.solve_s);
  more = s;
  more.solver.element_size = 15;  // half the default: four times the elements
  EXPECT_GT(estimate_cost(more).solve_s, 2 * base.solve_s);
  more = s;
  more.camera.width *= 2;
  more.camera.antialias *= 2;
  const CostEstimate wider = estimate_render_cost(more);
  EXPECT_EQ(wider.render_mesh_s, base.render_mesh_s);
  EXPECT_NEAR(wider.render_s - wider.render_mesh_s, 8 * (base.render_s - base.render_mesh_s),
              1e-9 * base.render_s);
  EXPECT_EQ(estimate_cost(more).solve_s, base.solve_s);
  more = s;
  // A tolerance: error estimates, at most one a third of the unshot power and one for the
  // pixels, and the image at kToleranceAntialias rays a pixel across; its extra levels are
  // bounded by the job's time instead.
  more.solver.tolerance = 0.02;
  const CostEstimate tolerant = estimate_cost(more);
  EXPECT_GT(tolerant.solve_s, base.solve_s);
  EXPECT_NE(tolerant.solve_terms.find("up to 5 error estimates"), std::string::npos)
      << tolerant.solve_terms;  // 0.1 % down to 1e-4: 2 + ceil(log3 10)
  EXPECT_NEAR(tolerant.render_s - tolerant.render_mesh_s, 4 * (base.render_s - base.render_mesh_s),
              1e-9 * base.render_s);  // the built-in's 2 x 2 rays a pixel: 4 x 4
}

// The built-in scenes solve and render in 4-12 s here (README); the estimate must not be
// far below that, nor so high that a default limit of 10 minutes would refuse them, with or
// without a tolerance.
TEST(Cost, BuiltInScenesAreEstimatedNearWhatTheyTakeAndWellInsideTheLimit) {
  for (const char* name : {"cornell", "wrinkled-box", "paper-room"}) {
    CostEstimate e = estimate_cost(builtin(name));
    EXPECT_GT(e.solve_s + e.render_s, 2.0) << name;
    EXPECT_LT(e.solve_s + e.render_s, 60.0) << name;
    // A tolerance of 1 % is admitted too: its pixels and estimates are counted, its extra
    // levels bounded by the job's time (counted at 4 x 4 rays every round, paper-room was
    // estimated at 13 minutes, and its extra levels at 4 x the elements each, 37).
    Scene tolerant = builtin(name);
    tolerant.solver.tolerance = 0.01;
    e = estimate_cost(tolerant);
    EXPECT_LT(e.solve_s + e.render_s, 600.0) << name << " with a tolerance";
  }
}

// What the time estimate rests on, whatever the machine: the shots a solve takes to its
// unshot target. Measured: cornell 1,049 against 984 expected, wrinkled-box 660 against
// 682, paper-room 1,182 against 800 (its mirror's small patches reflect little diffusely);
// so within 0.6-1.5 here.
TEST(Cost, TheExpectedShotsAreTheShotsASolveTakes) {
  for (const char* name : {"cornell", "wrinkled-box", "paper-room"}) {
    const Scene scene = builtin(name);
    const double ratio = solve(scene).stats.shots / expected_shots(scene);
    EXPECT_GT(ratio, 0.6) << name;
    EXPECT_LT(ratio, 1.5) << name;
  }
  Scene capped = builtin("cornell");
  capped.solver.max_shots = 100;
  EXPECT_EQ(expected_shots(capped), 100);
}

// The near field of the scale report: a 1 m lamp 0.1 m over a floor in 64 x 64-element
// patches, 96 x 96 elements each, every floor element near. Its estimate was 0.056 s where
// two shots took 20.6 s (4 x 64 x 64 points a near receiver); with the points bounded at
// kNearFieldPoints they take 0.48 s, the estimate counts them, and says so.
TEST(Cost, ANearFieldIsCountedAsItIsBounded) {
  const Scene s = parse_scene(std::string_view(test::facing_quads_json(96, 64)));
  const CostEstimate e = estimate_cost(s);
  EXPECT_GT(e.solve_s - e.setup_s, 0.1) << e.solve_terms;
  EXPECT_LT(e.solve_s - e.setup_s, 2.0) << e.solve_terms;
  Scene far = s;  // the floor 10 m down: no near field
  for (Vec3& p : std::get<QuadShape>(far.objects[1].shape).corners) p.y -= 10;
  EXPECT_LT(estimate_cost(far).solve_s - estimate_cost(far).setup_s, 0.5 * (e.solve_s - e.setup_s))
      << estimate_cost(far).solve_terms;
}

// A million elements (two facing quads of 700 x 700, two shots) took 8.5 s to set up and
// shoot on the 2-core machine before the set-up could stop (job_runner_test's
// AJobStopsAtItsTimeLimitWhileItsMeshIsBuilt); without a set-up term the model said 2.9 s.
TEST(Cost, AMillionElementsAreEstimatedAboveWhatTheirSetUpTakes) {
  Scene s = parse_scene(std::string_view(test::facing_quads_json(700)));
  const CostEstimate e = estimate_cost(s);
  EXPECT_GT(e.solve_s, 8.5) << e.solve_terms;
  EXPECT_GT(e.setup_s, 0.5 * e.solve_s) << "most of it is set-up";
  // At one ray a pixel: at the default 2 x 2 the model's per-hit term for the lamp's half
  // million elements outweighs the mesh (render/lights.cpp takes far patches whole, which
  // the model does not count; it over-estimates such a lamp, never under-estimates it).
  s.camera.antialias = 1;
  const CostEstimate one_ray = estimate_cost(s);
  EXPECT_GT(one_ray.render_mesh_s, 0.5 * one_ray.render_s)
      << "a 16 x 16 image of a million elements";
}

// The requests of the hostile-input report: hours, not minutes.
TEST(Cost, TheReportedHostageRequestsAreEstimatedInHours) {
  Scene job = parse_scene(std::string_view(test::small_scene_json(10)));
  job.solver.element_size = 0.03;
  job.solver.hemicube_resolution = 1024;
  job.solver.max_shots = 1'000'000;
  job.solver.unshot_fraction = 0;  // never met: every shot is spent
  CostEstimate e = estimate_cost(job);
  EXPECT_GT(e.solve_s, 3600) << e.solve_terms;
  EXPECT_NE(e.solve_terms.find("about 1,000,000 shots at hemi-cube 1,024"), std::string::npos)
      << e.solve_terms;
  Scene view = builtin("paper-room");
  view.camera.width = view.camera.height = 8192;
  view.camera.antialias = 8;
  view.camera.glossy_samples = 256;
  EXPECT_GT(estimate_render_cost(view).render_s, 3600);
  EXPECT_NE(estimate_render_cost(view).render_terms.find("8,192x8,192 pixels, 64 rays a pixel"),
            std::string::npos)
      << estimate_render_cost(view).render_terms;
}

}  // namespace
}  // namespace bumprad
