#include "evaluation/metrics.h"

#include <gtest/gtest.h>

#include <map>

namespace dslam {
namespace {

SE3 At(double x, double y, double z, double yaw = 0.0) {
  return SE3(Eigen::AngleAxisd(yaw, Vec3::UnitY()).toRotationMatrix(), Vec3(x, y, z));
}

TEST(CameraMetrics, HandComputedTranslationErrors) {
  // Steps of 1 m; the estimate overshoots the first by 0.1 m and undershoots the second by 0.1 m.
  const std::vector<SE3> gt = {At(0, 0, 0), At(0, 0, 1), At(0, 0, 2)};
  const std::vector<SE3> est = {At(0, 0, 0), At(0, 0, 1.1), At(0, 0, 2)};
  const CameraMetrics m = ComputeCameraMetrics(gt, est);
  EXPECT_NEAR(m.path_length_m, 2.0, 1e-12);
  ASSERT_TRUE(m.rte_pct && m.rre_deg_per_m);
  EXPECT_NEAR(*m.rte_pct, 100.0 * 0.2 / 2.0, 1e-9);
  EXPECT_NEAR(*m.rre_deg_per_m, 0.0, 1e-9);
  EXPECT_NEAR(m.ate_m, std::sqrt(0.01 / 3.0), 1e-12);
  EXPECT_FALSE(m.mean_step_te_m);
}

TEST(CameraMetrics, HandComputedRotationError) {
  // The second step turns 0.02 rad too much; its translation is right in the first frame, so the
  // relative error of the last step is a pure rotation of 0.02 rad.
  const std::vector<SE3> gt = {At(0, 0, 0), At(0, 0, 1), At(0, 0, 2)};
  const std::vector<SE3> est = {At(0, 0, 0), At(0, 0, 1), At(0, 0, 2, 0.02)};
  const CameraMetrics m = ComputeCameraMetrics(gt, est);
  EXPECT_NEAR(*m.rte_pct, 0.0, 1e-9);
  EXPECT_NEAR(*m.rre_deg_per_m, 0.02 * kRadToDeg / 2.0, 1e-9);
}

TEST(CameraMetrics, ShortPathReportsMeanAbsoluteStepErrors) {
  const std::vector<SE3> gt = {At(0, 0, 0), At(0, 0, 0.1), At(0, 0, 0.2)};
  const std::vector<SE3> est = {At(0, 0, 0), At(0, 0, 0.13), At(0, 0, 0.2)};
  const CameraMetrics m = ComputeCameraMetrics(gt, est);
  EXPECT_FALSE(m.rte_pct);
  EXPECT_FALSE(m.rre_deg_per_m);
  ASSERT_TRUE(m.mean_step_te_m && m.mean_step_re_deg);
  EXPECT_NEAR(*m.mean_step_te_m, (0.03 + 0.03) / 2.0, 1e-9);
}

TEST(CameraMetrics, MismatchedLengthsAreAnError) {
  EXPECT_THROW(ComputeCameraMetrics({At(0, 0, 0)}, {At(0, 0, 0), At(0, 0, 1)}), std::invalid_argument);
}

TEST(StructureMetric, HandComputedRse) {
  // |est - gt| = 0.5 and 0; |gt| = 10 and 5 -> RSE = 100 * 0.5 / 15.
  const auto rse = ComputeRsePct({{Vec3(0, 0, 10.5), Vec3(0, 0, 10)}, {Vec3(3, 4, 0), Vec3(3, 4, 0)}});
  ASSERT_TRUE(rse);
  EXPECT_NEAR(*rse, 100.0 * 0.5 / 15.0, 1e-12);
  EXPECT_FALSE(ComputeRsePct({}));
}

ObjectPairSample Pair(const SE3& H_gt, const SE3& H_est, double speed_gt, double speed_est, bool estimated = true) {
  ObjectPairSample s;
  s.H_world_gt = H_gt;
  s.H_world_est = H_est;
  s.speed_gt_mps = speed_gt;
  s.window_speed_gt_mps = speed_gt;  // steady: the pair's speed is the second's around it
  s.speed_est_mps = speed_est;
  s.estimated = estimated;
  s.est_dynamic = true;
  return s;
}

TEST(ObjectMetrics, HandComputedMotionAndSpeedErrors) {
  // Pair 1: gt moves 1 m, estimate 1.1 m -> |t(E)| = 0.1. Pair 2: gt 2 m, exact.
  const std::vector<ObjectPairSample> samples = {Pair(At(1, 0, 0), At(1.1, 0, 0), 10.0, 11.0),
                                                 Pair(At(0, 0, 2), At(0, 0, 2), 20.0, 20.0)};
  const ObjectMetrics m = ComputeObjectMetrics(samples);
  EXPECT_NEAR(*m.omte_pct, 100.0 * 0.1 / 3.0, 1e-9);
  EXPECT_NEAR(*m.omre_deg_per_m, 0.0, 1e-9);
  EXPECT_NEAR(*m.omse_pct, 100.0 * 1.0 / 30.0, 1e-9);
  EXPECT_NEAR(*m.me_t_m, 0.05, 1e-9);
  EXPECT_NEAR(*m.speed_err_mps, 0.5, 1e-9);
  EXPECT_NEAR(*m.object_coverage, 1.0, 1e-12);
}

TEST(ObjectMetrics, RotationErrorPerMetre) {
  // gt: 2 m forward; estimate: the same plus a 0.01 rad turn.
  const ObjectMetrics m = ComputeObjectMetrics({Pair(At(0, 0, 2), At(0, 0, 2, 0.01), 20.0, 20.0)});
  EXPECT_NEAR(*m.omre_deg_per_m, 0.01 * kRadToDeg / 2.0, 1e-9);
  EXPECT_NEAR(*m.me_r_deg, 0.01 * kRadToDeg, 1e-9);
}

TEST(ObjectMetrics, ComparedInTheObjectBodyFrame) {
  // The same body-frame motion and error, seen from a world in which the object sits far away and
  // rotated: the errors must not change (they would with a world-frame comparison).
  const SE3 H_body_gt = At(0, 0, 1), H_body_est = At(0.1, 0, 1);
  const SE3 L = At(30, 0, -40, 1.2);
  ObjectPairSample far = Pair(L * H_body_gt * L.inverse(), L * H_body_est * L.inverse(), 10.0, 10.0);
  far.L_world_object_gt_prev = L;
  const ObjectMetrics a = ComputeObjectMetrics({far});
  const ObjectMetrics b = ComputeObjectMetrics({Pair(H_body_gt, H_body_est, 10.0, 10.0)});
  EXPECT_NEAR(*a.omte_pct, 10.0, 1e-9);
  EXPECT_NEAR(*a.omte_pct, *b.omte_pct, 1e-9);
}

TEST(ObjectMetrics, DroppedObjectLowersCoverageNotError) {
  std::vector<ObjectPairSample> samples = {Pair(At(1, 0, 0), At(1.1, 0, 0), 10.0, 11.0)};
  const ObjectMetrics full = ComputeObjectMetrics(samples);
  // A second object the method never estimated (and whose motion would have been badly wrong).
  samples.push_back(Pair(At(0, 0, 3), At(5, 5, 5), 30.0, 0.0, false));
  const ObjectMetrics dropped = ComputeObjectMetrics(samples);
  EXPECT_NEAR(*dropped.omte_pct, *full.omte_pct, 1e-12);
  EXPECT_NEAR(*dropped.omse_pct, *full.omse_pct, 1e-12);
  EXPECT_NEAR(*dropped.object_coverage, 0.5, 1e-12);
  EXPECT_EQ(dropped.gt_pairs, 2);
  EXPECT_EQ(dropped.estimated_pairs, 1);
}

TEST(ObjectMetrics, StaticPairsReportedSeparately) {
  ObjectPairSample parked = Pair(SE3::Identity(), At(0.02, 0, 0), 0.0, 0.2);
  parked.est_dynamic = true;  // wrongly called dynamic
  ObjectPairSample parked_ok = Pair(SE3::Identity(), SE3::Identity(), 0.5, 0.0);
  parked_ok.est_dynamic = false;
  const ObjectMetrics m = ComputeObjectMetrics({parked, parked_ok, Pair(At(1, 0, 0), At(1, 0, 0), 10.0, 10.0)});
  EXPECT_EQ(m.static_pairs_estimated, 2);
  EXPECT_EQ(m.moving_pairs_estimated, 1);
  EXPECT_NEAR(*m.static_mean_speed_mps, 0.1, 1e-12);
  EXPECT_NEAR(*m.static_false_dynamic_frac, 0.5, 1e-12);
  EXPECT_NEAR(*m.omte_pct, 0.0, 1e-12);  // static pairs stay out of the motion errors
}

TEST(ObjectMetrics, NothingEstimatedGivesNoErrors) {
  const ObjectMetrics m = ComputeObjectMetrics({Pair(At(1, 0, 0), At(1, 0, 0), 10.0, 0.0, false)});
  EXPECT_FALSE(m.omte_pct);
  EXPECT_FALSE(m.omse_pct);
  EXPECT_NEAR(*m.object_coverage, 0.0, 1e-12);
}

}  // namespace
}  // namespace dslam

namespace dslam {
namespace {
// A run that streams its estimates knows its ground-truth pairs first and the estimates later, in
// any order: the two-step accumulation must give what one pass gives.
TEST(ObjectMetrics, PairsFirstAndEstimatesLaterInAnyOrderEqualOnePass) {
  const std::vector<ObjectPairSample> samples = {Pair(At(1, 0, 0), At(1.1, 0, 0), 10.0, 11.0),
                                                 Pair(At(0, 0, 2), At(0, 0, 2.3), 20.0, 23.0),
                                                 Pair(At(0, 0, 2), At(0, 0, 2), 20.0, 0.0, false),
                                                 Pair(At(0, 0, 0.01), At(0, 0.2, 0), 0.1, 2.0)};
  const ObjectMetrics one_pass = ComputeObjectMetrics(samples);
  ObjectMetricsAccumulator two_steps;
  for (const ObjectPairSample& s : samples) two_steps.addPair(s);
  for (auto it = samples.rbegin(); it != samples.rend(); ++it)
    if (it->estimated) two_steps.addEstimate(*it);
  const ObjectMetrics m = two_steps.result();
  EXPECT_EQ(m.gt_pairs, 4);
  EXPECT_EQ(m.estimated_pairs, 3);
  EXPECT_EQ(m.static_pairs_estimated, 1);
  EXPECT_EQ(m.gt_moving_pairs, 3);
  EXPECT_NEAR(*m.object_coverage, 2.0 / 3.0, 1e-12);  // over the moving pairs
  EXPECT_NEAR(*one_pass.object_coverage, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(*m.omte_pct, *one_pass.omte_pct, 1e-12);
  EXPECT_NEAR(*m.omse_pct, *one_pass.omse_pct, 1e-12);
  EXPECT_NEAR(*m.static_mean_speed_mps, 2.0, 1e-12);
}

TEST(CameraMetrics, TheAccumulatorCountsItsPoses) {
  CameraMetricsAccumulator acc;
  EXPECT_EQ(acc.result().ate_m, 0.0);
  acc.add(At(0, 0, 0), At(0, 0, 0));
  acc.add(At(0, 0, 2), At(0, 0, 2.2));
  EXPECT_EQ(acc.poses(), 2);
  EXPECT_NEAR(acc.result().ate_m, std::sqrt(0.04 / 2.0), 1e-12);
  EXPECT_NEAR(*acc.result().rte_pct, 10.0, 1e-9);
}

// Coverage counts the moving pairs, and a second time the measurable ones among them: a moving pair whose
// object shows too little of the same surface in both frames lowers the first, not the second.
TEST(ObjectMetrics, CoverageOverMovingPairsAndOverMeasurableOnes) {
  ObjectPairSample seen = Pair(At(1, 0, 0), At(1, 0, 0), 10.0, 10.0);
  seen.measurable = true;
  ObjectPairSample hidden = Pair(At(1, 0, 0), At(1, 0, 0), 10.0, 0.0, false);
  hidden.measurable = false;  // e.g. a car behind another, two points of it in view
  ObjectPairSample missed = Pair(At(1, 0, 0), At(1, 0, 0), 10.0, 0.0, false);
  missed.measurable = true;
  ObjectPairSample parked = Pair(SE3::Identity(), SE3::Identity(), 0.0, 0.0, false);
  parked.measurable = true;  // static: in neither coverage
  const ObjectMetrics m = ComputeObjectMetrics({seen, hidden, missed, parked});
  EXPECT_EQ(m.gt_pairs, 4);
  EXPECT_EQ(m.gt_moving_pairs, 3);
  ASSERT_TRUE(m.measurable_moving_pairs);
  EXPECT_EQ(*m.measurable_moving_pairs, 2);
  EXPECT_NEAR(*m.object_coverage, 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(*m.object_coverage_measurable, 0.5, 1e-12);
  // Where the ground truth cannot tell, there is no measurable coverage.
  EXPECT_FALSE(ComputeObjectMetrics({Pair(At(1, 0, 0), At(1, 0, 0), 10.0, 10.0)}).object_coverage_measurable);
}


// A camera step 3 sigma too long along z and turned 1 sigma about x: NEES 9 + 1; only steps with a covariance count.
TEST(CameraMetrics, StepNeesByHand) {
  const double sigma_t = 0.02, sigma_r = 0.001;
  const SE3 step_gt(RotationExp(Vec3(0.0, 0.05, 0.0)), Vec3(0.1, 0.0, 1.0));
  const SE3 step_est(step_gt.rotation() * RotationExp(Vec3(sigma_r, 0.0, 0.0)),
                     step_gt.translation() + Vec3(0.0, 0.0, 3.0 * sigma_t));
  Mat6 covariance = Mat6::Zero();
  covariance.diagonal() << Vec3::Constant(sigma_t * sigma_t), Vec3::Constant(sigma_r * sigma_r);
  ASSERT_TRUE(CameraStepNees(step_gt, step_est, covariance));
  EXPECT_NEAR(*CameraStepNees(step_gt, step_est, covariance), 10.0, 1e-6);
  EXPECT_FALSE(CameraStepNees(step_gt, step_est, Mat6::Zero()));

  const SE3 T0, T1_gt = step_gt, T1_est = step_est, T2 = step_est * step_est;
  const std::map<int, Mat6> only_step_1 = {{1, covariance}};
  const CameraMetrics m = ComputeCameraMetrics({T0, T1_gt, T1_gt * step_gt}, {T0, T1_est, T2}, only_step_1);
  ASSERT_TRUE(m.camera_step_nees);
  EXPECT_NEAR(*m.camera_step_nees, 10.0, 1e-6);
  EXPECT_FALSE(ComputeCameraMetrics({T0, T1_gt}, {T0, T1_est}).camera_step_nees);
}

// NEES by hand: an error of 2 sigma in x of the anchored translation and 1 sigma about z gives 4 + 1.
TEST(ObjectMetrics, MotionNeesByHandAboutTheAnchor) {
  ObjectPairSample s = Pair(At(1, 0, 0), SE3(), 10.0, 10.0);
  const double sigma_t = 0.01, sigma_r = 0.002;
  s.anchor_est = Vec3(0.0, 0.0, 5.0);
  // Estimate: the true motion turned by sigma_r about z at the anchor, then moved 2 sigma along x.
  const SE3 turn_at_anchor = SE3(Mat3::Identity(), s.anchor_est) * SE3(RotationExp(Vec3(0, 0, sigma_r)), Vec3::Zero()) *
                             SE3(Mat3::Identity(), -s.anchor_est);
  s.H_world_est = SE3(Mat3::Identity(), Vec3(2 * sigma_t, 0, 0)) * s.H_world_gt * turn_at_anchor;
  s.covariance_est.diagonal() << Vec3::Constant(sigma_t * sigma_t), Vec3::Constant(sigma_r * sigma_r);
  const std::optional<double> nees = MotionNees(s);
  ASSERT_TRUE(nees);
  EXPECT_NEAR(*nees, 5.0, 1e-6);
  EXPECT_NEAR(*ComputeObjectMetrics({s}).motion_nees, 5.0, 1e-6);
  s.covariance_est.setZero();  // unknown: no NEES
  EXPECT_FALSE(MotionNees(s));
  EXPECT_FALSE(ComputeObjectMetrics({s}).motion_nees);
}

}  // namespace
}  // namespace dslam
