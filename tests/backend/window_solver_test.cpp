#include "backend/window_solver.h"

#include <gtest/gtest.h>

#include "backend/graph_solver.h"
#include "support/city_graph.h"

namespace dslam {
namespace {

using test::CityGraph;

TEST(WindowSolver, ReachesTheSameMinimumAsCeres) {
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  FactorGraph ceres_graph = CityGraph(8, params);
  FactorGraph ours = ceres_graph;
  SolveOptions batch;
  batch.last_frame = 7;
  batch.max_iterations = 100;
  batch.function_tolerance = 1e-12;
  SolveGraph(params, batch, &ceres_graph);
  WindowSolveOptions window;
  window.last_frame = 7;
  window.max_iterations = 100;
  window.function_tolerance = 1e-12;
  const WindowSolveSummary summary = SolveWindow(params, window, &ours);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  for (int k = 0; k < 8; ++k)
    EXPECT_TRUE(BlockToPose(ours.camera(k)).isApprox(BlockToPose(ceres_graph.camera(k)), 1e-6)) << k;
  ASSERT_FALSE(ours.motions.empty());
  for (const auto& [id, m] : ours.motions)
    EXPECT_TRUE(m.worldMotion().isApprox(ceres_graph.motions.at(id).worldMotion(), 1e-6)) << id;
}

TEST(WindowSolver, HeldCamerasDoNotMove) {
  BackendParams params;
  FactorGraph graph = CityGraph(5, params);
  const FactorGraph before = graph;
  WindowSolveOptions window;
  window.last_frame = 4;
  window.fix_cameras = true;
  SolveWindow(params, window, &graph);
  for (int k = 0; k < 5; ++k) EXPECT_TRUE(BlockToPose(graph.camera(k)).isApprox(BlockToPose(before.camera(k)), 0.0));
}

}  // namespace
}  // namespace dslam
