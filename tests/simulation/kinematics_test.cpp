#include "simulation/kinematics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dslam {
namespace {

TEST(Kinematics, AStraightCommandDrivesAlongTheHeading) {
  const GroundPose start{1.0, 2.0, std::atan2(3.0, 4.0)};  // heading (0.6, 0, 0.8)
  const auto path = IntegrateUnicycle(start, [](double) { return SpeedCommand{5.0, 0.0}; }, 11, 10.0);
  ASSERT_EQ(path.size(), 11u);
  EXPECT_DOUBLE_EQ(path[0].x, 1.0);
  EXPECT_DOUBLE_EQ(path[0].z, 2.0);
  // 1 s at 5 m/s along (0.6, 0.8).
  EXPECT_NEAR(path[10].x, 1.0 + 3.0, 1e-9);
  EXPECT_NEAR(path[10].z, 2.0 + 4.0, 1e-9);
  EXPECT_NEAR(path[10].yaw, start.yaw, 1e-12);
}

TEST(Kinematics, AConstantTurnFollowsItsCircle) {
  // 2 m/s turning at 0.5 rad/s: a circle of radius 4 m; after pi seconds the car has turned by pi/2.
  const double fps = 100.0;
  const int frames = static_cast<int>(std::round(M_PI * fps)) + 1;
  const auto path = IntegrateUnicycle({0.0, 0.0, 0.0}, [](double) { return SpeedCommand{2.0, 0.5}; }, frames, fps);
  const GroundPose end = path.back();
  const double t = (frames - 1) / fps;
  EXPECT_NEAR(end.yaw, 0.5 * t, 1e-9);
  // yaw turns +z toward +x: the centre of the circle is at (4, 0) and the car starts at its left.
  EXPECT_NEAR(end.x, 4.0 - 4.0 * std::cos(0.5 * t), 1e-4);
  EXPECT_NEAR(end.z, 4.0 * std::sin(0.5 * t), 1e-4);
  for (const GroundPose& p : path) EXPECT_NEAR(std::hypot(p.x - 4.0, p.z), 4.0, 1e-4);
}

TEST(Kinematics, TheCameraLooksAlongTheHeadingAndTheVehicleBoxAlongItsX) {
  const GroundPose pose{3.0, 7.0, 0.3};
  const Vec3 heading(std::sin(0.3), 0.0, std::cos(0.3));
  const SE3 camera = CameraPoseOnGround(pose);
  EXPECT_TRUE((camera.rotation() * Vec3::UnitZ()).isApprox(heading, 1e-12));
  EXPECT_TRUE((camera.rotation() * Vec3::UnitY()).isApprox(Vec3::UnitY(), 1e-12));  // y stays down
  EXPECT_TRUE(camera.translation().isApprox(Vec3(3.0, 0.0, 7.0), 1e-12));
  const SE3 vehicle = VehiclePoseOnGround(pose, 1.65);
  EXPECT_TRUE((vehicle.rotation() * Vec3::UnitX()).isApprox(heading, 1e-12));
  EXPECT_TRUE(vehicle.translation().isApprox(Vec3(3.0, 1.65, 7.0), 1e-12));  // on the ground below
}

}  // namespace
}  // namespace dslam
