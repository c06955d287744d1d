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
    if (s.estimated) {
      EXPECT_NEAR(s.speed_est_mps, s.speed_gt_mps, 1e-9);
    }
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

// The inverse map, which a stream uses to find the ground truth of each run motion as it arrives.
TEST(EvaluateRun, ARunsObjectIsFoundInTheGroundTruthPairByPair) {
  Sequence seq = CarDrivingAlongX();
  EXPECT_EQ(GroundTruthIdOf(seq.gt, 7, 2), 7);  // no mapping: the run's ids are the ground truth's
  EXPECT_EQ(GroundTruthIdOf(seq.gt, 3, 2), 3);
  seq.gt.run_object_ids.emplace();
  for (int k = 0; k <= 4; ++k) (*seq.gt.run_object_ids)[{k, 7}] = k < 4 ? 3 : 5;
  EXPECT_EQ(GroundTruthIdOf(seq.gt, 3, 2), 7);
  EXPECT_EQ(GroundTruthIdOf(seq.gt, 3, 4), std::nullopt);  // the pair 3 -> 4 changed id: no run object is it
  EXPECT_EQ(GroundTruthIdOf(seq.gt, 5, 4), std::nullopt);
  EXPECT_EQ(GroundTruthIdOf(seq.gt, 9, 2), std::nullopt);  // an object the ground truth does not have
  EXPECT_EQ(GroundTruthIdOf(seq.gt, 0, 2), std::nullopt);  // 0 is RunObjectId's "no estimate", never an object
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


// A pair is moving when the centroid's net displacement over about a second centred on it is 1 m/s or more:
// a parked car whose label jitters by 12 cm a frame (1.2 m/s pair by pair) is standing; a car at 2 m/s moves;
// one at 0.5 m/s does not. Near the ends of a track the window is what the track has.
TEST(EvaluateRun, APairIsMovingByItsCentroidsSpeedOverASecondNotByItsJitter) {
  GroundTruth gt;
  auto add = [&](int id, auto centroid) {
    ObjectGroundTruth o;
    o.object_id = id;
    for (int k = 0; k < 30; ++k) {
      o.centroid_world[k] = centroid(k);
      o.L_world_object[k] = SE3(Mat3::Identity(), centroid(k));
      o.observed_frames.insert(k);
    }
    gt.objects[id] = o;
  };
  add(1, [](int k) { return Vec3(k % 2 ? 0.12 : 0.0, 0.0, 10.0); });  // jitter
  add(2, [](int k) { return Vec3(0.2 * k, 0.0, 10.0); });              // 2 m/s at 10 Hz
  add(3, [](int k) { return Vec3(0.05 * k, 0.0, 10.0); });             // 0.5 m/s
  for (int k : {1, 2, 15, 29}) {
    const auto jitter = GroundTruthPair(gt, 10.0, 1, k), car = GroundTruthPair(gt, 10.0, 2, k),
               slow = GroundTruthPair(gt, 10.0, 3, k);
    ASSERT_TRUE(jitter && car && slow);
    EXPECT_NEAR(jitter->speed_gt_mps, 1.2, 1e-9) << k;  // the pair's own displacement, for OMSE
    EXPECT_FALSE(jitter->gtMoving()) << k << ": " << jitter->window_speed_gt_mps;
    EXPECT_TRUE(car->gtMoving()) << k;
    EXPECT_NEAR(car->window_speed_gt_mps, 2.0, 1e-9) << k;
    EXPECT_FALSE(slow->gtMoving()) << k;
    EXPECT_FALSE(car->measurable.has_value());  // this ground truth does not say
  }
  gt.objects[2].measurable_frames = std::set<int>{15};
  EXPECT_EQ(GroundTruthPair(gt, 10.0, 2, 15)->measurable, std::optional<bool>(true));
  EXPECT_EQ(GroundTruthPair(gt, 10.0, 2, 16)->measurable, std::optional<bool>(false));
}

}  // namespace
}  // namespace dslam
