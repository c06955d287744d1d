#pragma once
// A LiDAR-like scan sampled from a depth image: the beams of a spinning LiDAR at the camera's centre (by
// default the 64 elevations of a Velodyne HDL-64E, +2 to -24.8 degrees, and its 0.17-degree azimuth step
// at 10 Hz), each returning the depth image's point where it meets the image. On a rendered scene, whose
// depth is exact, it measures the LiDAR mask source against the scene's exact masks (bench_lidar_masks).

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "geometry/pinhole_camera.h"

namespace dslam {

struct LidarBeamPattern {
  int beams = 64;
  double top_elevation_deg = 2.0;
  double bottom_elevation_deg = -24.8;
  double azimuth_step_deg = 0.17;
  void validate() const;
};

// Points in the camera frame (metres); beams that meet no valid depth give none. `depth_m`: CV_32FC1.
std::vector<Eigen::Vector3f> ScanFromDepth(const cv::Mat& depth_m, const PinholeCamera& camera,
                                           const LidarBeamPattern& pattern = {});

}  // namespace dslam
