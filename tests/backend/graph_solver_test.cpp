#include "backend/graph_solver.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "backend/factors/pose_block.h"
#include "support/city_graph.h"

namespace dslam {
namespace {

using test::CityGraph;

TEST(GraphSolver, TheBatchSolveRunsToItsOptimum) {
  // A long path's slow drift is weakly observed. Ceres' default first trust region (1e4) damped every
  // step along it, and a relative tolerance of 1e-6 on a cost summed over many residuals then stopped
  // the solve centimetres short on KITTI replay 0005. Solving on from the default solve's result with a
  // far tighter tolerance must now leave the cameras where they are (4 um here).
  ScenarioOptions opt;
  opt.num_frames = 50;
  opt.noise.point_sigma_m = 0.04;
  const Sequence seq = MakeScenario("city", opt);
  std::vector<FrameMeasurement> labelled = seq.frames;
  LabelDynamicObjects(ClassifierParams{}, seq.frame_rate_hz, &labelled);
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  params.noise.point_sigma_m = 0.04;
  FactorGraph graph;
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  for (const auto& f : labelled) builder.addFrame(f);
  FactorGraph stopped_early = graph;
  SolveOptions solve;
  solve.last_frame = graph.numFrames() - 1;
  solve.max_iterations = params.max_iterations_batch;
  solve.function_tolerance = params.batch_function_tolerance;
  SolveGraph(params, solve, &graph);
  SolveOptions old = solve;
  old.function_tolerance = 1e-6;
  old.initial_trust_region_radius = 1e4;
  SolveGraph(params, old, &stopped_early);
  FactorGraph optimum = graph;
  SolveOptions to_the_end = solve;
  to_the_end.function_tolerance = 1e-12;
  to_the_end.max_iterations = 5;
  SolveGraph(params, to_the_end, &optimum);
  auto largest_move_m = [&](const FactorGraph& g) {
    double largest = 0.0;
    for (int k = 0; k < g.numFrames(); ++k)
      largest = std::max(largest, (BlockToPose(g.camera(k)).translation() - BlockToPose(optimum.camera(k)).translation()).norm());
    return largest;
  };
  EXPECT_LT(largest_move_m(graph), 2e-5);
  EXPECT_GT(largest_move_m(stopped_early), 1e-4);  // where the old settings stopped (0.24 mm here)
}

TEST(GraphSolver, LowersTheCostAndHoldsCamerasWhenAsked) {
  BackendParams params;
  FactorGraph graph = CityGraph(6, params);
  const FactorGraph start = graph;
  SolveOptions solve;
  solve.last_frame = 5;
  SolveOptions held = solve;
  held.fix_cameras = true;
  const SolveSummary summary = SolveGraph(params, solve, &graph);
  EXPECT_TRUE(summary.usable);
  EXPECT_GT(summary.num_residual_blocks, 0);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  FactorGraph objects_only = start;
  const SolveSummary objects = SolveGraph(params, held, &objects_only);
  EXPECT_TRUE(objects.usable);
  EXPECT_LE(objects.final_cost, objects.initial_cost);
  for (int k = 0; k < 6; ++k) {
    EXPECT_TRUE(BlockToPose(objects_only.camera(k)).isApprox(BlockToPose(start.camera(k)), 0.0)) << k;
  }
  bool a_motion_moved = false;
  for (const auto& [id, m] : objects_only.motions)
    a_motion_moved |= !m.worldMotion().isApprox(start.motions.at(id).worldMotion(), 1e-12);
  EXPECT_TRUE(a_motion_moved);
}

// A range that starts after frame 0 holds what only earlier frames observe, and has no prior on camera 0.
TEST(GraphSolver, ARangeHoldsTheFramesBeforeIt) {
  BackendParams params;
  FactorGraph graph = CityGraph(6, params);
  const FactorGraph start = graph;
  SolveOptions solve;
  solve.first_frame = 3;
  solve.last_frame = 5;
  const SolveSummary summary = SolveGraph(params, solve, &graph);
  EXPECT_TRUE(summary.usable);
  for (int k = 0; k < 3; ++k)
    EXPECT_TRUE(BlockToPose(graph.camera(k)).isApprox(BlockToPose(start.camera(k)), 0.0)) << k;
  bool moved = false;
  for (int k = 3; k < 6; ++k) moved |= !BlockToPose(graph.camera(k)).isApprox(BlockToPose(start.camera(k)), 1e-12);
  EXPECT_TRUE(moved);
}

}  // namespace
}  // namespace dslam
