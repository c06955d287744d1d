#pragma once
// sensor_msgs/PointCloud2 <-> a LiDAR scan ("x y z intensity" in the LiDAR's frame), with every check a
// sample from the network needs: float32 x, y, z fields inside the point, data length = row_step x
// height, row_step >= width x point_step, little-endian, a bounded size. Errors are returned as a message
// naming the topic and the problem; nothing throws on bad samples.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "sensor_msgs_PointCloud2.h"

namespace dslam {

struct DecodedPointCloud {
  std::vector<Eigen::Vector4f> points;  // x y z intensity (0 without an intensity field); non-finite dropped
  std::string error;                    // empty when decoded
};

// At most this many points a scan (a 128-beam LiDAR gives about 260 000 a turn).
constexpr uint64_t kMaxPointCloudPoints = 4'000'000;

DecodedPointCloud DecodePointCloud(const sensor_msgs::msg::PointCloud2& msg);
// The inverse: one row of float32 x, y, z, intensity (16 bytes a point), as a Velodyne driver sends.
sensor_msgs::msg::PointCloud2 EncodePointCloud(const std::vector<Eigen::Vector4f>& points, int64_t t_ns,
                                               const std::string& frame_id);

}  // namespace dslam
