#pragma once
// KITTI Velodyne scans: float32 records "x y z reflectance" in the LiDAR frame.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace dslam {

// Throws std::runtime_error naming the file when it cannot be read or its size is not a whole number
// of 16-byte records (a truncated scan).
std::vector<Eigen::Vector4f> ReadVelodyneScan(const std::string& path);

}  // namespace dslam
