#pragma once
// Planar motion on flat ground for simulated vehicles and cameras. Frames follow docs/design.md §1:
// x right, y down, z forward; yaw turns +z toward +x; the ground plane is y = ground_y.

#include <functional>
#include <vector>

#include "geometry/se3.h"

namespace dslam {

struct GroundPose {
  double x = 0.0;
  double z = 0.0;
  double yaw = 0.0;  // heading direction (sin yaw, 0, cos yaw)
};

struct SpeedCommand {
  double speed_mps = 0.0;
  double yaw_rate_radps = 0.0;
};

// Samples the path of a unicycle at `frames` instants 1/fps apart (first sample = start); the
// command is a function of time since the start, integrated with fine sub-steps.
std::vector<GroundPose> IntegrateUnicycle(const GroundPose& start, const std::function<SpeedCommand(double)>& command,
                                          int frames, double fps);

// Camera looking along the heading, at height 0 (the ground is below it).
SE3 CameraPoseOnGround(const GroundPose& pose);
// Object body frame as KITTI boxes: origin at the bottom centre on the ground, x along the heading,
// y down, i.e. rotation R_y(yaw - pi/2).
SE3 VehiclePoseOnGround(const GroundPose& pose, double ground_y);

}  // namespace dslam
