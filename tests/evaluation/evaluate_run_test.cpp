#include "evaluation/evaluate_run.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

// A car (ground-truth id 7) driving 1 m a frame along x over frames 0..4, seen in every frame.
Sequence CarDrivingAlongX() {
  Sequence seq;
  seq.frame_rate_hz = 10.0;
  ObjectGroundTruth car;
  car.object_id = 7;
  for (int k = 0; k <= 4; ++k) {
    seq.gt.T_world_camera.push_back(SE3());
    car.L_world_object[k] = SE3(Mat3::Identity(), Vec3(k, 0.0, 10.0));
    car.centroid_world[k] = Vec3(k, 0.0, 10.0);
    car.observed_frames.insert(k);
  }
  seq.gt.objects[7] = car;
  return seq;
}

// The estimate of object `id` over frame - 1 -> frame: 1 m along x, as the car moves.
ObjectMotionEstimate Motion(int id, int frame) {
  ObjectMotionEstimate m;
  m.object_id = id;
  m.frame = frame;
  m.H_world = SE3(Mat3::Identity(), Vec3(1.0, 0.0, 0.0));
  m.speed_mps = 10.0;
  return m;
}

TEST(EvaluateRun, ARunsOwnObjectIdsAreMatchedToTheGroundTruthFrameByFrame) {
  Sequence seq = CarDrivingAlongX();
  Estimate est;
  est.T_world_camera.assign(5, SE3());
  for (int k = 1; k <= 4; ++k) est.object_motions.push_back(Motion(k < 4 ? 3 : 5, k));  // restarted as 5 at 4
  // Without a mapping the ids must be the ground truth's: run object 3 is not car 7.
  for (const ObjectPairSample& s : BuildObjectSamples(seq, est)) EXPECT_FALSE(s.estimated) << s.frame;

  // The run called the car 3 up to frame 3, then 5 (its track restarted in frame 4).
  seq.gt.run_object_ids.emplace();
  for (int k = 0; k <= 4; ++k) (*seq.gt.run_object_ids)[{k, 7}] = k < 4 ? 3 : 5;
  EXPECT_EQ(RunObjectId(seq.gt, 7, 2), 3);
  EXPECT_EQ(RunObjectId(seq.gt, 7, 4), 0);  // 3 at frame 3, 5 at frame 4: no estimate of that pair
  const std::vector<ObjectPairSample> samples = BuildObjectSamples(seq, est);
  ASSERT_EQ(samples.size(), 4u);
  for (const ObjectPairSample& s : samples) {
    EXPECT_EQ(s.object_id, 7);
    EXPECT_EQ(s.estimated, s.frame < 4) << s.frame;
    if (s.estimated) EXPECT_NEAR(s.speed_est_mps, s.speed_gt_mps, 1e-9);
  }
  const MethodMetrics m = EvaluateEstimate(seq, est, true);
  ASSERT_TRUE(m.objects && m.objects->object_coverage);
  EXPECT_NEAR(*m.objects->object_coverage, 0.75, 1e-12);  // 3 of the car's 4 pairs

  // A frame in which the run has no object on the car: the pairs on either side of it have no estimate.
  seq.gt.run_object_ids->erase({2, 7});
  EXPECT_EQ(RunObjectId(seq.gt, 7, 2), 0);
  EXPECT_EQ(RunObjectId(seq.gt, 7, 3), 0);
  EXPECT_EQ(RunObjectId(seq.gt, 7, 1), 3);
}

TEST(EvaluateRun, WithoutAMappingTheGroundTruthIdsAreTheRuns) {
  const Sequence seq = CarDrivingAlongX();
  EXPECT_EQ(RunObjectId(seq.gt, 7, 3), 7);
  Estimate est;
  est.T_world_camera.assign(5, SE3());
  for (int k = 1; k <= 4; ++k) est.object_motions.push_back(Motion(7, k));
  const MethodMetrics m = EvaluateEstimate(seq, est, true);
  ASSERT_TRUE(m.objects && m.objects->object_coverage && m.objects->omse_pct);
  EXPECT_NEAR(*m.objects->object_coverage, 1.0, 1e-12);
  EXPECT_NEAR(*m.objects->omse_pct, 0.0, 1e-9);
}

}  // namespace
}  // namespace dslam
