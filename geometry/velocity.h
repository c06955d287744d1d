#pragma once

#include "geometry/se3.h"

namespace dslam {

// Linear velocity of a rigid object over one frame transition, in metres per frame:
// v = t_H - (I - R_H) * c_prev, the displacement of the object point that was at c_prev.
inline Vec3 ObjectVelocityPerFrame(const SE3& H_world, const Vec3& c_prev_world) {
  return H_world.translation() - (Mat3::Identity() - H_world.rotationMatrix()) * c_prev_world;
}

inline double SpeedMps(const Vec3& velocity_per_frame, double frame_rate_hz) {
  return velocity_per_frame.norm() * frame_rate_hz;
}

constexpr double kMpsToKmh = 3.6;

}  // namespace dslam
