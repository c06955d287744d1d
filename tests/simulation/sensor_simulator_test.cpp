#include "simulation/sensor_simulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

namespace dslam {
namespace {

// A camera driving 1 m a frame along +z past a wall of points, a box 10 m ahead (seen) and one 30 m ahead
// (beyond the object range), the near box hidden in frame 2.
SimWorld SmallWorld() {
  SimWorld world;
  world.name = "small";
  for (int k = 0; k < 4; ++k) world.T_world_camera.push_back(SE3(Mat3::Identity(), Vec3(0.0, 0.0, k)));
  for (int i = 0; i < 20; ++i) world.static_points_world.push_back(Vec3(-3.0 + 0.3 * i, -1.0, 15.0));
  for (const auto& [id, z] : {std::pair{1, 10.0}, std::pair{2, 33.0}}) {
    SimObject obj;
    obj.object_id = id;
    obj.surface = SampleBox(4.0, 2.0, 1.5, 0.3);
    obj.centroid_body = Vec3(0.0, -0.75, 0.0);
    // Driving away at 1 m a frame, like the camera: the near box stays 10 m ahead.
    for (int k = 0; k < 4; ++k) obj.L_world_object[k] = SE3(Mat3::Identity(), Vec3(0.0, 1.0, z + k));
    world.objects.push_back(obj);
  }
  world.objects[0].occluded_frames = {2};
  return world;
}

TEST(SensorSimulator, WithoutNoiseItMeasuresTheTruthInTheCameraFrame) {
  SimNoise noise;
  noise.point_sigma_m = 0.0;
  const Sequence seq = SimulateSensor(SmallWorld(), SensorModel{}, noise, 1);
  ASSERT_EQ(seq.frames.size(), 4u);
  for (const FrameMeasurement& f : seq.frames) {
    const SE3 T_camera_world = seq.gt.T_world_camera[f.frame_index].inverse();
    EXPECT_EQ(f.static_points.size(), 20u) << f.frame_index;
    for (const PointObservation& p : f.static_points)
      EXPECT_TRUE(p.p_camera.isApprox(T_camera_world * seq.gt.static_points_world.at(p.track_id), 1e-12));
    for (const ObjectObservation& o : f.objects)
      for (const PointObservation& p : o.points) {
        Vec3 world;
        ASSERT_TRUE(seq.gt.pointWorld(p.track_id, f.frame_index, &world));
        EXPECT_TRUE(p.p_camera.isApprox(T_camera_world * world, 1e-12));
      }
    EXPECT_EQ(f.t_ns, static_cast<int64_t>(f.frame_index * 1e8));  // 10 Hz
  }
  // The far box is never seen; the near one is, except where it is hidden.
  EXPECT_TRUE(seq.gt.objects.at(2).observed_frames.empty());
  EXPECT_EQ(seq.gt.objects.at(1).observed_frames, (std::set<int>{0, 1, 3}));
  EXPECT_TRUE(seq.frames[2].objects.empty());
  // A pair is measurable when the same surface points are seen in both frames: 0 -> 1 only (hidden in 2,
  // so 2 -> 3 has nothing of frame 2 to compare with).
  ASSERT_TRUE(seq.gt.objects.at(1).measurable_frames.has_value());
  EXPECT_EQ(*seq.gt.objects.at(1).measurable_frames, (std::set<int>{1}));
  // Only the faces turned to the camera: straight behind it and below its top, that is the rear face (9 m
  // ahead), not the sides, the top or the far face.
  ASSERT_EQ(seq.frames[0].objects.size(), 1u);
  EXPECT_GE(seq.frames[0].objects[0].points.size(), 6u);
  for (const PointObservation& p : seq.frames[0].objects[0].points) EXPECT_NEAR(p.p_camera.z(), 9.0, 1e-9);
}

TEST(SensorSimulator, OdometryNoiseIsProportionalToTheStepWithFloors) {
  SimNoise noise;
  std::mt19937_64 rng(3);
  const SE3 step(RotationExp(Vec3(0.0, 0.2, 0.0)), Vec3(0.0, 0.0, 2.0));
  const OdometryMeasurement m = NoisyOdometry(step, noise, rng);
  EXPECT_NEAR(m.sigma[2], 0.05 * 2.0, 1e-12);  // 5 % of the translation, per axis
  EXPECT_NEAR(m.sigma[4], 0.10 * 0.2, 1e-12);  // 10 % of the rotation angle
  const OdometryMeasurement still = NoisyOdometry(SE3::Identity(), noise, rng);
  EXPECT_NEAR(still.sigma[0], noise.odom_translation_floor_m, 1e-15);
  EXPECT_NEAR(still.sigma[3], noise.odom_rotation_floor_rad, 1e-15);
  EXPECT_FALSE(m.T_prev_curr.isApprox(step, 1e-9));  // perturbed
}

TEST(SensorSimulator, RefusesWorldsItCannotMeasure) {
  SimWorld one_frame = SmallWorld();
  one_frame.T_world_camera.resize(1);
  EXPECT_THROW(SensorSimulator(one_frame, SensorModel{}, SimNoise{}, 1), std::invalid_argument);
  SimWorld pose_outside = SmallWorld();
  pose_outside.objects[0].L_world_object[9] = SE3::Identity();
  EXPECT_THROW(SensorSimulator(pose_outside, SensorModel{}, SimNoise{}, 1), std::invalid_argument);
  SimNoise bad;
  bad.odom_translation_floor_m = 0.0;
  EXPECT_THROW(SensorSimulator(SmallWorld(), SensorModel{}, bad, 1), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
