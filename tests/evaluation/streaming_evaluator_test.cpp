#include "evaluation/streaming_evaluator.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "backend/methods.h"
#include "frontend/dynamic_object_classifier.h"
#include "simulation/scenarios.h"

namespace dslam {
namespace {

void ExpectNear(const std::optional<double>& a, const std::optional<double>& b, const char* what) {
  ASSERT_EQ(a.has_value(), b.has_value()) << what;
  if (a) {
    EXPECT_NEAR(*a, *b, 1e-9 * std::max(1.0, std::abs(*b))) << what;
  }
}

// Fed the estimates one by one, points before their cameras, it reads what EvaluateEstimate reads from the
// whole estimate at the end.
TEST(StreamingEvaluator, EqualsTheEvaluationOfTheCollectedEstimate) {
  ScenarioOptions opt;
  opt.num_frames = 30;
  const Sequence seq = MakeScenario("city", opt);
  std::vector<FrameMeasurement> labelled = seq.frames;
  LabelDynamicObjects(ClassifierParams{}, seq.frame_rate_hz, &labelled);
  const Estimate est = RunMethod(Method::kOurs, BackendParams{}, seq.frame_rate_hz, labelled).estimate;
  ASSERT_FALSE(est.object_motions.empty());
  ASSERT_FALSE(est.points.empty());

  StreamingEvaluator streaming(seq.gt, seq.frame_rate_hz, true);
  for (const auto& f : labelled) streaming.frameMade(f);
  for (const auto& p : est.points) streaming.pointFinal(p);
  for (const auto& m : est.object_motions) streaming.motionFinal(m);
  for (int k = 0; k < static_cast<int>(est.T_world_camera.size()); ++k) {
    if (est.camera_step_covariance.count(k)) streaming.cameraStepCovariance(k, est.camera_step_covariance.at(k));
    streaming.cameraFinal(k, est.T_world_camera[k]);
  }
  const MethodMetrics got = streaming.metrics();
  const MethodMetrics want = EvaluateEstimate(seq, est, true);

  EXPECT_NEAR(got.camera.ate_m, want.camera.ate_m, 1e-9);
  EXPECT_NEAR(got.camera.path_length_m, want.camera.path_length_m, 1e-9);
  ExpectNear(got.camera.rte_pct, want.camera.rte_pct, "rte");
  ExpectNear(got.camera.rre_deg_per_m, want.camera.rre_deg_per_m, "rre");
  EXPECT_EQ(est.camera_step_covariance.size(), est.T_world_camera.size() - 1);  // every step but into frame 0
  ASSERT_TRUE(want.camera.camera_step_nees);
  ExpectNear(got.camera.camera_step_nees, want.camera.camera_step_nees, "camera step nees");
  ExpectNear(got.rse_pct, want.rse_pct, "rse");
  ASSERT_TRUE(got.objects && want.objects);
  EXPECT_EQ(got.objects->gt_pairs, want.objects->gt_pairs);
  EXPECT_EQ(got.objects->estimated_pairs, want.objects->estimated_pairs);
  EXPECT_GT(got.objects->estimated_pairs, 0);
  ExpectNear(got.objects->omte_pct, want.objects->omte_pct, "omte");
  ExpectNear(got.objects->omse_pct, want.objects->omse_pct, "omse");
  ExpectNear(got.objects->object_coverage, want.objects->object_coverage, "coverage");
  ExpectNear(got.objects->static_false_dynamic_frac, want.objects->static_false_dynamic_frac, "false dynamic");
  EXPECT_FALSE(streaming.objects().empty());
}

TEST(StreamingEvaluator, AMethodWithoutObjectsHasNoObjectMetrics) {
  ScenarioOptions opt;
  opt.num_frames = 5;
  const Sequence seq = MakeScenario("city", opt);
  StreamingEvaluator streaming(seq.gt, seq.frame_rate_hz, false);
  for (int k = 0; k < 5; ++k) {
    streaming.frameMade(seq.frames[k]);
    streaming.cameraFinal(k, seq.gt.T_world_camera[k]);
  }
  const MethodMetrics m = streaming.metrics();
  EXPECT_FALSE(m.objects.has_value());
  EXPECT_NEAR(m.camera.ate_m, 0.0, 1e-12);  // the ground truth against itself
}

// A frame made but never final, or a point whose camera never came, is a broken run, not a score.
TEST(StreamingEvaluator, RefusesToScoreARunThatLeftFramesOrPointsBehind) {
  ScenarioOptions opt;
  opt.num_frames = 3;
  const Sequence seq = MakeScenario("city", opt);
  StreamingEvaluator missing_camera(seq.gt, seq.frame_rate_hz, true);
  for (int k = 0; k < 3; ++k) missing_camera.frameMade(seq.frames[k]);
  missing_camera.cameraFinal(0, seq.gt.T_world_camera[0]);
  missing_camera.cameraFinal(1, seq.gt.T_world_camera[1]);
  EXPECT_THROW(missing_camera.metrics(), std::logic_error);

  StreamingEvaluator waiting_point(seq.gt, seq.frame_rate_hz, true);
  waiting_point.frameMade(seq.frames[0]);
  waiting_point.cameraFinal(0, seq.gt.T_world_camera[0]);
  waiting_point.pointFinal({1, 5, -1, Vec3(0.0, 0.0, 5.0)});  // frame 1 never made final
  EXPECT_THROW(waiting_point.metrics(), std::logic_error);
}

}  // namespace
}  // namespace dslam
