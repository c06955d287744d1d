#pragma once
// Topic names (DDS names of ROS 2 topics: "rt/" + the ROS name). A vehicle's topics live under its
// namespace: rt/<vehicle>/camera/color/image_raw; without a vehicle name, rt/camera/color/image_raw.

#include <string>

namespace dslam {

struct VehicleTopics {
  std::string colour, depth, mask, odometry;           // inputs
  std::string camera_odometry, object_motions, status;  // outputs
};

inline VehicleTopics TopicsFor(const std::string& vehicle) {
  const std::string ns = vehicle.empty() ? "rt/" : "rt/" + vehicle + "/";
  return {ns + "camera/color/image_raw",        ns + "camera/depth/image_raw", ns + "camera/instance_mask",
          ns + "odom",                          ns + "dslam/camera_odometry", ns + "dslam/object_motions",
          ns + "dslam/status"};
}

}  // namespace dslam
