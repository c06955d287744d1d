#pragma once
// Topic names (DDS names of ROS 2 topics: "rt/" + the ROS name). A vehicle's topics live under its
// namespace: rt/<vehicle>/camera/color/image_raw; without a vehicle name, rt/camera/color/image_raw.
// The LiDAR: rt/<vehicle>/lidar/points. Each image topic has its compressed form beside it, as ROS 2's
// image_transport names it: <image topic>/compressed (sensor_msgs/CompressedImage).

#include <string>

namespace dslam {

struct VehicleTopics {
  std::string colour, depth, mask, odometry;           // inputs
  std::string camera_odometry, object_motions, status;  // outputs
  std::string markers;                                  // output for RViz
  std::string lidar;                                    // input when masks come from the LiDAR (PointCloud2)
  std::string colour_compressed, depth_compressed, mask_compressed;  // inputs, sensor_msgs/CompressedImage
};

// Empty when `vehicle` can name a vehicle: "" (no namespace) or ROS 2 name tokens ([A-Za-z_][A-Za-z0-9_]*)
// joined by '/'. The name is a topic namespace and a results folder under --out: "..", an absolute path
// or characters ROS 2 refuses would put either somewhere else.
inline std::string FindInvalidVehicleName(const std::string& vehicle) {
  if (vehicle.empty()) return {};
  auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  bool token_start = true;
  for (char c : vehicle) {
    if (c == '/') {
      if (token_start) break;  // empty token: leading, trailing or doubled '/'
      token_start = true;
      continue;
    }
    if (!(alpha(c) || (!token_start && digit(c))))
      return "vehicle name '" + vehicle + "' is not a ROS 2 namespace: use letters, digits and '_' (not first), tokens joined by '/'";
    token_start = false;
  }
  if (token_start)
    return "vehicle name '" + vehicle + "' is not a ROS 2 namespace: an empty token (leading, trailing or doubled '/')";
  return {};
}

// Empty when `name` is a ROS 2 node name ([A-Za-z_][A-Za-z0-9_]*), else why not.
inline std::string FindInvalidNodeName(const std::string& name) {
  const auto allowed = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  };
  bool ok = !name.empty() && !(name[0] >= '0' && name[0] <= '9');
  for (char c : name) ok = ok && allowed(c);
  return ok ? std::string() : "node name '" + name + "' is not a ROS 2 node name: letters, digits and '_', not a digit first";
}

inline VehicleTopics TopicsFor(const std::string& vehicle) {
  const std::string ns = vehicle.empty() ? "rt/" : "rt/" + vehicle + "/";
  VehicleTopics t{ns + "camera/color/image_raw",        ns + "camera/depth/image_raw", ns + "camera/instance_mask",
                  ns + "odom",                          ns + "dslam/camera_odometry", ns + "dslam/object_motions",
                  ns + "dslam/status",                  ns + "dslam/markers", ns + "lidar/points", {}, {}, {}};
  t.colour_compressed = t.colour + "/compressed";
  t.depth_compressed = t.depth + "/compressed";
  t.mask_compressed = t.mask + "/compressed";
  return t;
}

}  // namespace dslam
