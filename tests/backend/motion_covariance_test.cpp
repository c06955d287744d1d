// Issue 13: each object motion carries its marginal covariance from the smoother's information, and
// the speed its standard deviation; on simulation the sigma must be calibrated.
#include <gtest/gtest.h>

#include <cmath>

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

TEST(MotionCovariance, TheSpeedSigmaOfTheSlidingWindowIsCalibratedOnTheSimulatedCity) {
  ScenarioOptions opt;
  opt.num_frames = 300;  // one cycle of the city: accelerating, braking, turning and stopping cars
  const Sequence seq = MakeScenario("city", opt);
  std::vector<FrameMeasurement> frames = seq.frames;
  LabelDynamicObjects(ClassifierParams{}, seq.frame_rate_hz, &frames);
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  params.schedule = {ScheduleKind::kSlidingWindow, 10};
  const MethodResult ours = RunMethod(Method::kOurs, params, seq.frame_rate_hz, frames);

  int n = 0, within_1 = 0, within_3 = 0;
  for (const ObjectPairSample& s : BuildObjectSamples(seq, ours.estimate)) {
    if (!s.estimated || !s.est_dynamic || !s.gtMoving()) continue;
    ASSERT_GT(s.speed_sigma_est_mps, 0.0) << "object " << s.object_id << " frame " << s.frame;
    // The covariance is a covariance: symmetric, positive definite.
    EXPECT_LT((s.covariance_est - s.covariance_est.transpose()).norm(), 1e-9 * s.covariance_est.norm());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat6>(s.covariance_est).eigenvalues().minCoeff(), 0.0);
    const double error = std::abs(s.speed_est_mps - s.speed_gt_mps);
    ++n;
    within_1 += error <= s.speed_sigma_est_mps;
    within_3 += error <= 3.0 * s.speed_sigma_est_mps;
  }
  ASSERT_GT(n, 300);
  const double frac_1 = static_cast<double>(within_1) / n, frac_3 = static_cast<double>(within_3) / n;
  std::cout << "speed errors within 1 sigma: " << frac_1 << ", within 3 sigma: " << frac_3 << " (" << n << " pairs)"
            << std::endl;
  // A Gaussian: 68 % and 99.7 %. Neither far overconfident nor uselessly wide.
  EXPECT_GT(frac_1, 0.5);
  EXPECT_LT(frac_1, 0.85);
  EXPECT_GT(frac_3, 0.9);
}

}  // namespace
}  // namespace dslam
