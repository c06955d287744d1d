#include "backend/exact_marginalisation.h"

// The exact fixed-lag smoother (BackendParams::marginalisation = exact) against what it must equal: a
// fixed lag of W frames makes camera m final from the measurements of frames 0..m+W-1, so with exact
// marginalisation camera m is the batch optimum of that prefix, up to the linearisation the prior froze
// (which grows with the run: 16 frames here; docs/results.md, "The exact fixed lag", for long runs).

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <vector>

#include "backend/estimator.h"
#include "frontend/dynamic_object_classifier.h"
#include "simulation/scenarios.h"
#include "support/city_graph.h"
#include "support/final_estimates.h"

namespace dslam {
namespace {

std::vector<FrameMeasurement> Labelled(const std::string& scenario, int frames, double* rate_hz) {
  ScenarioOptions options;
  options.num_frames = frames;
  const Sequence seq = MakeScenario(scenario, options);
  std::vector<FrameMeasurement> labelled = seq.frames;
  LabelDynamicObjects(ClassifierParams{}, seq.frame_rate_hz, &labelled);
  *rate_hz = seq.frame_rate_hz;
  return labelled;
}

BackendParams Converging(BackendParams params) {
  params.max_iterations_batch = params.max_iterations_window = 100;
  params.batch_function_tolerance = params.window_function_tolerance = 1e-12;
  return params;
}

Estimate Run(const BackendParams& params, double rate_hz, const std::vector<FrameMeasurement>& frames) {
  Estimator estimator(params, rate_hz);
  for (const FrameMeasurement& f : frames) estimator.addFrame(f);
  return estimator.finish();
}

double TranslationGap(const SE3& a, const SE3& b) { return (a.translation() - b.translation()).norm(); }

// Camera m of each estimator against the batch optimum of frames 0..m+W-1.
struct Gaps {
  double exact = 0.0, sparsified = 0.0;
};

Gaps GapsToPrefixBatch(const std::string& scenario, int frames, MotionMode mode, int window) {
  double rate_hz = 0.0;
  const std::vector<FrameMeasurement> measured = Labelled(scenario, frames, &rate_hz);
  BackendParams batch = Converging(BackendParams{});
  batch.default_mode = mode;
  BackendParams exact = batch;
  exact.schedule = {ScheduleKind::kSlidingWindow, window};
  exact.marginalisation = Marginalisation::kExact;
  BackendParams sparsified = exact;
  sparsified.marginalisation = Marginalisation::kSparsified;
  const Estimate e = Run(exact, rate_hz, measured), s = Run(sparsified, rate_hz, measured);
  Gaps gaps;
  for (int m = 0; m + window <= frames - 1; ++m) {
    const std::vector<FrameMeasurement> prefix(measured.begin(), measured.begin() + m + window);
    const Estimate reference = Run(batch, rate_hz, prefix);
    gaps.exact = std::max(gaps.exact, TranslationGap(e.T_world_camera[m], reference.T_world_camera[m]));
    gaps.sparsified = std::max(gaps.sparsified, TranslationGap(s.T_world_camera[m], reference.T_world_camera[m]));
  }
  std::printf("%s: exact %.3g m, sparsified %.3g m\n", scenario.c_str(), gaps.exact, gaps.sparsified);
  return gaps;
}

TEST(ExactFixedLag, EachCameraIsThePrefixBatchOptimumOnASceneWithoutStaticStructure) {
  const Gaps gaps = GapsToPrefixBatch("paper", 16, MotionMode::kConstant, 5);
  EXPECT_LT(gaps.exact, 1e-3);
  EXPECT_LT(gaps.exact, 0.1 * gaps.sparsified);
}

TEST(ExactFixedLag, EachCameraIsThePrefixBatchOptimumWithAMotionPerFrame) {
  // The sparsified window is already close here (its object points leave exactly); the exact one is closer.
  const Gaps gaps = GapsToPrefixBatch("paper", 16, MotionMode::kSmoothed, 5);
  EXPECT_LT(gaps.exact, 1e-3);
  EXPECT_LT(gaps.exact, 0.5 * gaps.sparsified);
}

// Per variable type, on the simulated city's first frames (landmarks, moving objects with a motion per
// frame tied by smoothness), frames 0 and 1 leaving in turn: what leaves, what the prior is on, what is final.
TEST(ExactFixedLag, EachVariableTypeLeavesWithTheLastFrameThatRefersToIt) {
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  FactorGraph graph = test::CityGraph(6, params);
  // Before: camera 1's landmarks that frame 2 still sees, frame 1's object points with a successor at 2,
  // the motions into 1 (leave with frame 1) and into 2 (tied to them by smoothness: stay, in the prior).
  std::set<int> landmarks_kept, landmarks_gone, successors, into_1, into_2;
  for (const auto& e : graph.frame(1).measurements) {
    const PointVariable& p = graph.points.at(e.point_var);
    if (p.object_id < 0) (p.last_frame >= 2 ? landmarks_kept : landmarks_gone).insert(e.point_var);
  }
  for (const auto& pm : graph.frame(2).point_motions) successors.insert(pm.curr_point_var);
  for (const auto& [id, h] : graph.motions) {
    if (h.last_frame == 1) into_1.insert(id);
    if (h.first_frame == 2 && h.last_frame == 2) into_2.insert(id);
  }
  ASSERT_FALSE(landmarks_kept.empty());
  ASSERT_FALSE(landmarks_gone.empty());
  ASSERT_FALSE(successors.empty());
  ASSERT_FALSE(into_1.empty());
  ASSERT_FALSE(into_2.empty());
  const std::vector<int> leaving = LeavingKeys(graph, 1, false);
  auto leaves = [&](VariableKind kind, int id) {
    return std::binary_search(leaving.begin(), leaving.end(), VariableKey(kind, id));
  };
  EXPECT_TRUE(leaves(VariableKind::kCamera, 1));
  EXPECT_FALSE(leaves(VariableKind::kCamera, 2));
  for (int v : landmarks_gone) EXPECT_TRUE(leaves(VariableKind::kPoint, v)) << v;
  for (int v : landmarks_kept) EXPECT_FALSE(leaves(VariableKind::kPoint, v)) << v;
  for (int id : into_1) EXPECT_TRUE(leaves(VariableKind::kMotion, id)) << id;
  for (int id : into_2) EXPECT_FALSE(leaves(VariableKind::kMotion, id)) << id;
  const size_t frame_1_points = graph.frame(1).measurements.size();

  test::FinalEstimates sink;
  MarginaliseFrameExactly(params, 10.0, 0, false, &graph, &sink);
  MarginaliseFrameExactly(params, 10.0, 1, false, &graph, &sink);

  EXPECT_EQ(sink.cameras, (std::vector<int>{0, 1}));
  EXPECT_EQ(graph.first_stored_frame, 2);
  size_t final_at_1 = 0;
  for (const PointEstimate& p : sink.points) final_at_1 += p.frame == 1 ? 1 : 0;
  EXPECT_EQ(final_at_1, frame_1_points);
  // Each transition into frame 1 is final (its motion left); none into 2 is.
  for (const ObjectMotionEstimate& m : sink.motions) EXPECT_LE(m.frame, 1);
  for (const ObjectTransition& tr : graph.transitions) EXPECT_GE(tr.frame, 2);
  for (int key : leaving) {
    const int id = IdOfKey(key);
    if (KindOfKey(key) == VariableKind::kPoint) {
      EXPECT_FALSE(graph.points.count(id)) << "point " << id;
    } else if (KindOfKey(key) == VariableKind::kMotion) {
      EXPECT_FALSE(graph.motions.count(id)) << "motion " << id;
    }
  }
  // No factor refers to what left; the prior is on what they were tied to.
  for (int k = graph.first_stored_frame; k < graph.numFrames(); ++k) {
    const FrameFactors& f = graph.frame(k);
    for (const auto& e : f.measurements) EXPECT_TRUE(graph.points.count(e.point_var));
    for (const auto& e : f.point_motions)
      EXPECT_TRUE(graph.points.count(e.prev_point_var) && graph.motions.count(e.motion_var));
    for (const auto& e : f.smoothness) EXPECT_TRUE(graph.motions.count(e.prev_motion_var));
  }
  EXPECT_FALSE(graph.frame(2).odometry.has_value()) << "camera 1's odometry into 2 is in the prior";
  ASSERT_TRUE(graph.dense_prior.has_value());
  const DensePrior& prior = *graph.dense_prior;
  auto in_prior = [&](VariableKind kind, int id) {
    return std::find(prior.keys.begin(), prior.keys.end(), VariableKey(kind, id)) != prior.keys.end();
  };
  EXPECT_TRUE(in_prior(VariableKind::kCamera, 2));
  for (int v : landmarks_kept) EXPECT_TRUE(in_prior(VariableKind::kPoint, v)) << v;
  for (int v : successors) EXPECT_TRUE(in_prior(VariableKind::kPoint, v)) << v;
  for (int id : into_2) EXPECT_TRUE(in_prior(VariableKind::kMotion, id)) << id;
  int dim = 0;
  for (int key : prior.keys) dim += TangentDimOfKey(key);
  ASSERT_EQ(prior.R.cols(), dim);
  ASSERT_EQ(prior.lin.size(), prior.keys.size());
  // The prior is linearised where its variables are now, and its information is positive definite.
  const Eigen::LLT<Eigen::MatrixXd> information(prior.R.transpose() * prior.R);
  EXPECT_EQ(information.info(), Eigen::Success);
  EXPECT_EQ(prior.R.rows(), dim);
}

// SLAM+MOT's object stage holds the cameras: they are not variables, and a held camera's measurements of
// landmarks that stay become part of the prior on those landmarks.
TEST(ExactFixedLag, WithTheCamerasHeldOnlyPointsAndMotionsAreInThePrior) {
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  FactorGraph graph = test::CityGraph(4, params);
  std::set<int> landmarks_kept;
  for (const auto& e : graph.frame(0).measurements)
    if (graph.points.at(e.point_var).object_id < 0 && graph.points.at(e.point_var).last_frame >= 1)
      landmarks_kept.insert(e.point_var);
  ASSERT_FALSE(landmarks_kept.empty());
  const std::vector<int> leaving = LeavingKeys(graph, 0, true);
  for (int key : leaving) EXPECT_NE(KindOfKey(key), VariableKind::kCamera);
  test::FinalEstimates sink;
  MarginaliseFrameExactly(params, 10.0, 0, true, &graph, &sink);
  ASSERT_TRUE(graph.dense_prior.has_value());
  for (int key : graph.dense_prior->keys) EXPECT_NE(KindOfKey(key), VariableKind::kCamera);
  const std::vector<int>& keys = graph.dense_prior->keys;
  for (int v : landmarks_kept)
    EXPECT_NE(std::find(keys.begin(), keys.end(), VariableKey(VariableKind::kPoint, v)), keys.end()) << v;
  EXPECT_EQ(sink.cameras, (std::vector<int>{0}));
}

// Only consecutive frames leave, from the front.
TEST(ExactFixedLag, RefusesAFrameThatIsNotTheWindowsFirst) {
  BackendParams params;
  FactorGraph graph = test::CityGraph(4, params);
  test::FinalEstimates sink;
  EXPECT_THROW(MarginaliseFrameExactly(params, 10.0, 1, false, &graph, &sink), std::logic_error);
}

}  // namespace
}  // namespace dslam

