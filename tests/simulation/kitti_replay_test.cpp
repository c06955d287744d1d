#include "simulation/kitti_replay.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

// A made-up KITTI-like ground truth: 20 frames driving 1 m a frame, a car 8 m ahead keeping its distance,
// a car 30 m ahead (beyond the paper's 22 m gate).
KittiGroundTruthSequence Straight() {
  KittiGroundTruthSequence gt;
  gt.name = "straight";
  for (int k = 0; k < 20; ++k) gt.T_world_camera.push_back(SE3(Mat3::Identity(), Vec3(0.0, 0.0, k)));
  for (const auto& [id, z] : {std::pair{1, 8.0}, std::pair{2, 30.0}}) {
    KittiObjectTrack car;
    car.object_id = id;
    car.h = 1.5, car.w = 1.7, car.l = 4.0;
    // KITTI's box frame: x along the car; facing away from us, R_y(-pi/2).
    const Mat3 R = Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitY()).toRotationMatrix();
    for (int k = 0; k < 20; ++k) car.T_camera_object[k] = SE3(R, Vec3(0.0, 1.65, z));
    gt.objects[id] = car;
  }
  return gt;
}

TEST(KittiReplay, SeededAndDeterministic) {
  KittiReplayOptions o;
  const Sequence a = MakeKittiReplay(Straight(), o), b = MakeKittiReplay(Straight(), o);
  o.seed = 2;
  const Sequence c = MakeKittiReplay(Straight(), o);
  ASSERT_EQ(a.frames.size(), 20u);
  ASSERT_FALSE(a.frames[5].static_points.empty());
  EXPECT_EQ(a.frames[5].static_points[0].p_camera, b.frames[5].static_points[0].p_camera);
  EXPECT_NE(a.frames[5].static_points[0].p_camera, c.frames[5].static_points[0].p_camera);
}

TEST(KittiReplay, ObjectsAreGatedByDistanceAndTheirCentroidIsTheBoxCentre) {
  const Sequence seq = MakeKittiReplay(Straight(), KittiReplayOptions{});
  EXPECT_EQ(seq.gt.objects.at(1).observed_frames.size(), 20u);
  EXPECT_TRUE(seq.gt.objects.at(2).observed_frames.empty());
  // (X, Y - h/2, Z) in the camera: the box's centre, half its height above its bottom.
  const Vec3 centroid = seq.gt.T_world_camera[3].inverse() * seq.gt.objects.at(1).centroid_world.at(3);
  EXPECT_TRUE(centroid.isApprox(Vec3(0.0, 1.65 - 0.75, 8.0), 1e-9));
  for (const FrameMeasurement& f : seq.frames) {
    ASSERT_EQ(f.objects.size(), 1u);
    EXPECT_EQ(f.objects[0].object_id, 1);
  }
}

TEST(KittiReplay, PointNoiseHasTheConfiguredSigma) {
  KittiReplayOptions o;
  o.noise.point_sigma_m = 0.04;
  const Sequence seq = MakeKittiReplay(Straight(), o);
  double sum_sq = 0.0;
  int n = 0;
  for (const FrameMeasurement& f : seq.frames) {
    const SE3 T_camera_world = seq.gt.T_world_camera[f.frame_index].inverse();
    for (const PointObservation& p : f.static_points) {
      sum_sq += (p.p_camera - T_camera_world * seq.gt.static_points_world.at(p.track_id)).squaredNorm();
      n += 3;
    }
  }
  ASSERT_GT(n, 3000);
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.04, 0.002);
}

}  // namespace
}  // namespace dslam
