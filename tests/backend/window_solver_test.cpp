#include "backend/window_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include "backend/graph_solver.h"
#include "support/city_graph.h"

namespace dslam {
namespace {

using test::CityGraph;

// Both solvers run to their optimum over frames 0..last.
template <typename Options>
Options Converged(int last_frame) {
  Options options;
  options.last_frame = last_frame;
  options.max_iterations = 100;
  options.function_tolerance = 1e-12;
  return options;
}

TEST(WindowSolver, ReachesTheSameMinimumAsCeres) {
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  FactorGraph ceres_graph = CityGraph(8, params);
  FactorGraph ours = ceres_graph;
  SolveGraph(params, Converged<SolveOptions>(7), &ceres_graph);
  const auto window = Converged<WindowSolveOptions>(7);
  const WindowSolveSummary summary = SolveWindow(params, window, &ours);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  for (int k = 0; k < 8; ++k)
    EXPECT_TRUE(BlockToPose(ours.camera(k)).isApprox(BlockToPose(ceres_graph.camera(k)), 1e-6)) << k;
  ASSERT_FALSE(ours.motions.empty());
  for (const auto& [id, m] : ours.motions)
    EXPECT_TRUE(m.worldMotion().isApprox(ceres_graph.motions.at(id).worldMotion(), 1e-6)) << id;
}

// The solve stops at the first accepted step whose decrease, or the next one predicted from the last two, is
// under the tolerance; what the skipped steps would have taken is under the tolerance too.
TEST(WindowSolver, StopsWhenTheNextFallIsPredictedUnderTheTolerance) {
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  FactorGraph graph = CityGraph(8, params);
  FactorGraph converged = graph;
  WindowSolveOptions window;
  window.last_frame = 7;
  window.function_tolerance = 1e-3;
  const WindowSolveSummary summary = SolveWindow(params, window, &graph);
  const std::vector<double>& d = summary.relative_decreases;
  ASSERT_GE(d.size(), 2u);
  const double tol = window.function_tolerance;
  auto stops_at = [&](size_t i) { return d[i] < tol || (i > 0 && d[i] * d[i] / d[i - 1] < tol); };
  for (size_t i = 0; i + 1 < d.size(); ++i) EXPECT_FALSE(stops_at(i)) << i;
  EXPECT_TRUE(stops_at(d.size() - 1));
  EXPECT_GE(d.back(), tol);  // the prediction stopped it: the fall alone would have asked for another step
  const WindowSolveSummary optimum = SolveWindow(params, Converged<WindowSolveOptions>(7), &converged);
  EXPECT_GT(optimum.num_iterations, summary.num_iterations);
  EXPECT_LT((summary.final_cost - optimum.final_cost) / summary.final_cost, tol);
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

// A threshold small enough that the kernel weighs some smoothness factors of the city's moving objects.
TEST(WindowSolver, WithARobustSmoothnessReachesTheSameMinimumAsCeres) {
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  params.noise.smoothness_huber_delta = 0.05;
  FactorGraph ceres_graph = CityGraph(8, params);
  FactorGraph ours = ceres_graph;
  FactorGraph quadratic = ceres_graph;
  SolveGraph(params, Converged<SolveOptions>(7), &ceres_graph);
  const auto window = Converged<WindowSolveOptions>(7);
  SolveWindow(params, window, &ours);
  BackendParams plain = params;
  plain.noise.smoothness_huber_delta = 0.0;
  SolveWindow(plain, window, &quadratic);
  // Reweighting converges linearly where the kernel bends: the two solvers stop micrometres apart.
  const auto apart_m = [](const SE3& a, const SE3& b) { return (a.translation() - b.translation()).norm(); };
  double moved_by_kernel_m = 0.0;
  for (const auto& [id, m] : ours.motions) {
    EXPECT_LT(apart_m(m.worldMotion(), ceres_graph.motions.at(id).worldMotion()), 1e-5) << id;
    moved_by_kernel_m = std::max(moved_by_kernel_m, apart_m(m.worldMotion(), quadratic.motions.at(id).worldMotion()));
  }
  for (int k = 0; k < 8; ++k)
    EXPECT_LT(apart_m(BlockToPose(ours.camera(k)), BlockToPose(ceres_graph.camera(k))), 1e-5) << k;
  EXPECT_GT(moved_by_kernel_m, 1e-3);  // the kernel was active
}

// One moving object breaks the motion model for a frame (every point of it shifted by 0.4 m, as a box
// label that jitters): how far that moves the cameras, with the smoothness factor quadratic and robust.
double CameraPullOfAJump(double smoothness_huber_delta) {
  constexpr int kFrames = 10, kJumpFrame = 5;
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  params.noise.smoothness_huber_delta = smoothness_huber_delta;
  const std::vector<FrameMeasurement> clean = test::LabelledCityFrames(kFrames);
  std::vector<FrameMeasurement> jumped = clean;
  ObjectObservation* jumper = nullptr;
  for (ObjectObservation& o : jumped[kJumpFrame].objects)
    if (o.is_dynamic && o.reported == ReportedMotion::kMoving && (!jumper || o.points.size() > jumper->points.size()))
      jumper = &o;
  EXPECT_NE(jumper, nullptr);
  if (!jumper) return 0.0;
  for (PointObservation& p : jumper->points) p.p_camera += Vec3(0.4, 0.0, 0.0);
  const auto solve = [&](const std::vector<FrameMeasurement>& frames) {
    FactorGraph graph = test::GraphOf(frames, params);
    SolveGraph(params, Converged<SolveOptions>(kFrames - 1), &graph);
    std::vector<SE3> cameras;
    for (int k = 0; k < kFrames; ++k) cameras.push_back(BlockToPose(graph.camera(k)));
    return cameras;
  };
  const std::vector<SE3> before = solve(clean), after = solve(jumped);
  double pull_m = 0.0;
  for (int k = 0; k < kFrames; ++k)
    pull_m = std::max(pull_m, (before[k].translation() - after[k].translation()).norm());
  return pull_m;
}

TEST(WindowSolver, AnObjectThatBreaksTheMotionModelPullsTheCamerasLessThroughARobustSmoothness) {
  const double quadratic_m = CameraPullOfAJump(0.0), robust_m = CameraPullOfAJump(1.0);
  std::cout << "camera pull of a 0.4 m jump: quadratic " << quadratic_m << " m, robust " << robust_m << " m"
            << std::endl;
  EXPECT_GT(quadratic_m, 1e-4);  // the jump does reach the cameras through a quadratic smoothness
  EXPECT_LT(robust_m, 0.5 * quadratic_m);
}

}  // namespace
}  // namespace dslam
