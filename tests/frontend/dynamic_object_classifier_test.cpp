#include "frontend/dynamic_object_classifier.h"

#include <gtest/gtest.h>

#include <random>

namespace dslam {
namespace {

// Camera moving forward 1 m per frame, turning slightly; points observed from both frames.
struct TwoFrames {
  FrameMeasurement prev, curr;
  SE3 T_prev_curr;
};

TwoFrames MakeFrames(const SE3& object_motion_world, bool with_static, bool with_odometry) {
  TwoFrames f;
  const SE3 T0 = SE3::Identity();
  const SE3 T1(Eigen::AngleAxisd(0.02, Vec3::UnitY()).toRotationMatrix(), Vec3(0.1, 0.0, 1.0));
  f.T_prev_curr = T0.inverse() * T1;
  f.prev.frame_index = 0;
  f.curr.frame_index = 1;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  if (with_static) {
    for (int i = 0; i < 40; ++i) {
      const Vec3 l(8.0 * u(rng), 2.0 * u(rng), 20.0 + 10.0 * u(rng));
      f.prev.static_points.push_back({i, T0.inverse() * l});
      f.curr.static_points.push_back({i, T1.inverse() * l});
    }
  }
  if (with_odometry) f.curr.odometry = OdometryMeasurement{f.T_prev_curr, Vec6::Constant(0.01)};
  ObjectObservation a, b;
  a.object_id = b.object_id = 3;
  for (int i = 0; i < 30; ++i) {
    const Vec3 l(2.0 + u(rng), 0.5 * u(rng), 12.0 + 2.0 * u(rng));
    a.points.push_back({1000 + i, T0.inverse() * l});
    b.points.push_back({1000 + i, T1.inverse() * (object_motion_world * l)});
  }
  f.prev.objects.push_back(a);
  f.curr.objects.push_back(b);
  return f;
}

TEST(DynamicObjectClassifier, CameraMotionFromStaticPoints) {
  TwoFrames f = MakeFrames(SE3::Identity(), true, false);
  const DynamicObjectClassifier c(ClassifierParams{}, 10.0);
  EXPECT_TRUE(c.cameraMotion(f.prev, f.curr).isApprox(f.T_prev_curr, 1e-6));
}

TEST(DynamicObjectClassifier, ParkedObjectIsStaticMovingObjectIsDynamic) {
  const DynamicObjectClassifier c(ClassifierParams{}, 10.0);
  TwoFrames parked = MakeFrames(SE3::Identity(), true, false);
  c.label(parked.prev, &parked.curr);
  EXPECT_FALSE(parked.curr.objects[0].is_dynamic);

  // 0.3 m per frame = 3 m/s.
  TwoFrames moving = MakeFrames(SE3(Eigen::Quaterniond::Identity(), Vec3(0.0, 0.0, 0.3)), true, false);
  c.label(moving.prev, &moving.curr);
  EXPECT_TRUE(moving.curr.objects[0].is_dynamic);
  EXPECT_NEAR(c.objectSpeedMps(moving.prev.objects[0], moving.curr.objects[0], moving.T_prev_curr), 3.0, 1e-6);
}

TEST(DynamicObjectClassifier, FallsBackToOdometryWithoutStaticPoints) {
  const DynamicObjectClassifier c(ClassifierParams{}, 10.0);
  TwoFrames parked = MakeFrames(SE3::Identity(), false, true);
  c.label(parked.prev, &parked.curr);
  EXPECT_FALSE(parked.curr.objects[0].is_dynamic);
  // Without odometry nor static points the camera is assumed still: the parked object seems to move.
  TwoFrames blind = MakeFrames(SE3::Identity(), false, false);
  c.label(blind.prev, &blind.curr);
  EXPECT_TRUE(blind.curr.objects[0].is_dynamic);
}

TEST(DynamicObjectClassifier, NewObjectStaysDynamic) {
  const DynamicObjectClassifier c(ClassifierParams{}, 10.0);
  TwoFrames f = MakeFrames(SE3::Identity(), true, false);
  f.curr.objects[0].object_id = 99;  // not in the previous frame
  f.curr.objects[0].is_dynamic = false;
  c.label(f.prev, &f.curr);
  EXPECT_TRUE(f.curr.objects[0].is_dynamic);
}

TEST(DynamicObjectClassifier, RejectsBadParameters) {
  ClassifierParams p;
  p.dynamic_speed_threshold_mps = -1.0;
  EXPECT_THROW(DynamicObjectClassifier(p, 10.0), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
