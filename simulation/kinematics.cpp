#include "simulation/kinematics.h"

#include <cmath>

namespace dslam {
namespace {
Mat3 RotY(double angle) { return Eigen::AngleAxisd(angle, Vec3::UnitY()).toRotationMatrix(); }
}  // namespace

std::vector<GroundPose> IntegrateUnicycle(const GroundPose& start, const std::function<SpeedCommand(double)>& command,
                                          int frames, double fps) {
  constexpr int kSubSteps = 20;
  const double dt = 1.0 / (fps * kSubSteps);
  std::vector<GroundPose> path;
  path.reserve(frames);
  GroundPose p = start;
  double t = 0.0;
  for (int k = 0; k < frames; ++k) {
    path.push_back(p);
    for (int s = 0; s < kSubSteps; ++s) {
      // Midpoint rule: exact for constant speed on a straight line, second order on arcs.
      const SpeedCommand c = command(t + 0.5 * dt);
      const double yaw_mid = p.yaw + 0.5 * c.yaw_rate_radps * dt;
      p.x += c.speed_mps * dt * std::sin(yaw_mid);
      p.z += c.speed_mps * dt * std::cos(yaw_mid);
      p.yaw += c.yaw_rate_radps * dt;
      t += dt;
    }
  }
  return path;
}

SE3 CameraPoseOnGround(const GroundPose& pose) { return SE3(RotY(pose.yaw), Vec3(pose.x, 0.0, pose.z)); }

SE3 VehiclePoseOnGround(const GroundPose& pose, double ground_y) {
  return SE3(RotY(pose.yaw - M_PI / 2.0), Vec3(pose.x, ground_y, pose.z));
}

}  // namespace dslam
