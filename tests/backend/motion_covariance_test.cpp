// Issue 13: each object motion carries its marginal covariance from the smoother's information, and
// the speed its standard deviation; on simulation the sigma must be calibrated.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>

#include <Eigen/Eigenvalues>

#include "backend/marginalisation.h"
#include "backend/methods.h"
#include "evaluation/evaluate_run.h"
#include "frontend/dynamic_object_classifier.h"
#include "simulation/scenarios.h"

namespace dslam {
namespace {

TEST(MotionCovariance, SpeedSigmaFollowsTheTranslationAlongTheVelocity) {
  MotionVariable motion;
  motion.H_anchor = MotionVariable::AnchorBlock(SE3(Eigen::Quaterniond::Identity(), Vec3(0.5, 0.0, 0.0)), Vec3::Zero());
  motion.covariance.setZero();
  motion.covariance.diagonal() << 0.01 * 0.01, 0.04 * 0.04, 0.04 * 0.04, 0.0, 0.0, 0.0;
  // Moving along x: only the x variance counts, at 10 frames a second.
  EXPECT_NEAR(SpeedSigmaMps(motion, Vec3::Zero(), Vec3(0.5, 0.0, 0.0), 10.0), 0.1, 1e-12);
  // A rotation's uncertainty counts by the centroid's distance from the anchor: 1 mrad about z at 10 m
  // along y moves the centroid 1 cm along x.
  motion.covariance.setZero();
  motion.covariance(5, 5) = 1e-3 * 1e-3;
  EXPECT_NEAR(SpeedSigmaMps(motion, Vec3(0.0, 10.0, 0.0), Vec3(0.5, 0.0, 0.0), 10.0), 0.1, 1e-9);
  motion.covariance.setZero();
  EXPECT_EQ(SpeedSigmaMps(motion, Vec3::Zero(), Vec3(0.5, 0.0, 0.0), 10.0), 0.0);
}

// Fraction of moving pairs whose speed error is within 1 and 3 sigma, checking each covariance on the way.
struct Calibration {
  int pairs = 0;
  double within_1 = 0.0, within_3 = 0.0;
  double mean_nees = 0.0;  // of the 6-dof motions: 6 when the covariance is honest
  double camera_step_nees = 0.0;  // of the cameras' steps, likewise
};

Calibration SpeedCalibration(const std::string& schedule, int num_frames, uint64_t seed = 1) {
  ScenarioOptions opt;
  opt.num_frames = num_frames;
  opt.seed = seed;
  const Sequence seq = MakeScenario("city", opt);
  std::vector<FrameMeasurement> frames = seq.frames;
  LabelDynamicObjects(ClassifierParams{}, seq.frame_rate_hz, &frames);
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  params.schedule = ParseSchedule(schedule);
  const MethodResult ours = RunMethod(Method::kOurs, params, seq.frame_rate_hz, frames);

  Calibration c;
  int within_1 = 0, within_3 = 0;
  for (const ObjectPairSample& s : BuildObjectSamples(seq, ours.estimate)) {
    if (!s.estimated || !s.est_dynamic || !s.gtMoving()) continue;
    EXPECT_GT(s.speed_sigma_est_mps, 0.0) << "object " << s.object_id << " frame " << s.frame;
    // The covariance is a covariance: symmetric, positive definite.
    EXPECT_LT((s.covariance_est - s.covariance_est.transpose()).norm(), 1e-9 * s.covariance_est.norm());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat6>(s.covariance_est).eigenvalues().minCoeff(), 0.0);
    const double error = std::abs(s.speed_est_mps - s.speed_gt_mps);
    const std::optional<double> nees = MotionNees(s);
    EXPECT_TRUE(nees.has_value());
    c.mean_nees += nees.value_or(0.0);
    ++c.pairs;
    within_1 += error <= s.speed_sigma_est_mps;
    within_3 += error <= 3.0 * s.speed_sigma_est_mps;
  }
  c.within_1 = static_cast<double>(within_1) / std::max(1, c.pairs);
  c.within_3 = static_cast<double>(within_3) / std::max(1, c.pairs);
  c.mean_nees /= std::max(1, c.pairs);
  // The cameras' steps: every one but the first frame's carries its covariance.
  EXPECT_EQ(ours.estimate.camera_step_covariance.size(), seq.frames.size() - 1);
  for (const auto& [k, covariance] : ours.estimate.camera_step_covariance) {
    const std::optional<double> nees =
        CameraStepNees(seq.gt.T_world_camera[k - 1].inverse() * seq.gt.T_world_camera[k],
                       ours.estimate.T_world_camera[k - 1].inverse() * ours.estimate.T_world_camera[k], covariance);
    EXPECT_TRUE(nees.has_value()) << "frame " << k;
    c.camera_step_nees += nees.value_or(0.0) / static_cast<double>(seq.frames.size() - 1);
  }
  std::cout << schedule << ", seed " << seed << ": speed errors within 1 sigma: " << c.within_1 << ", within 3 sigma: " << c.within_3
            << ", motion NEES " << c.mean_nees << " (" << c.pairs << " pairs), camera step NEES "
            << c.camera_step_nees << std::endl;
  return c;
}

// A Gaussian: 68 % and 99.7 %. Neither far overconfident nor uselessly wide.
void ExpectCalibrated(const Calibration& c) {
  EXPECT_GT(c.within_1, 0.5);
  EXPECT_LT(c.within_1, 0.85);
  EXPECT_GT(c.within_3, 0.9);
  // The whole motion's covariance, not only the speed's: NEES within [0.5, 2] x its 6 dimensions.
  EXPECT_GT(c.mean_nees, 3.0);
  EXPECT_LT(c.mean_nees, 12.0);
  EXPECT_GT(c.camera_step_nees, 3.0);
  EXPECT_LT(c.camera_step_nees, 12.0);
}

TEST(MotionCovariance, TheSpeedSigmaOfTheSlidingWindowIsCalibratedOnTheSimulatedCity) {
  // One cycle of the city: accelerating, braking, turning and stopping cars; seeds 1-5 (noise and scene).
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Calibration c = SpeedCalibration("window:10", 300, seed);
    ASSERT_GT(c.pairs, 300);
    ExpectCalibrated(c);
  }
}

TEST(MotionCovariance, TheSpeedSigmaOfTheBatchIsCalibratedOnTheSimulatedCity) {
  // Batch: from the frames around each motion (the rest held), after the whole trajectory's solve.
  const Calibration c = SpeedCalibration("batch", 80);
  ASSERT_GT(c.pairs, 150);
  ExpectCalibrated(c);
}

}  // namespace
}  // namespace dslam
