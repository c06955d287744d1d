#pragma once
// Metric depth (CV_32FC1, metres along z, 0 = none) from the encodings datasets and drivers use.
// Invalid input (wrong pixel type, empty image, non-positive scale) throws std::invalid_argument.

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "geometry/pinhole_camera.h"

namespace dslam {

// 16-bit (or float) depth image divided by `units_per_metre` (1000 for millimetres); 0 stays "none".
cv::Mat DepthFromScaledImage(const cv::Mat& depth, double units_per_metre);

// Disparity image (pixels times `units_per_pixel`, e.g. 256 for KITTI's 16-bit disparity PNGs) to depth
// z = fx * baseline / disparity; disparities <= 0 give no depth.
cv::Mat DepthFromDisparity(const cv::Mat& disparity, double units_per_pixel, double fx_times_baseline_m);

struct StereoParams {
  int num_disparities = 128;  // multiple of 16
  int block_size = 5;         // odd
  int uniqueness_ratio = 10;
  // Left-right consistency: a pixel keeps its disparity only when the right image's own match points back
  // to it within this many pixels; occlusions and mismatches at object edges fail it. 0: no check.
  double lr_max_difference_px = 0.0;
  // "none", or "wls": OpenCV's edge-aware weighted-least-squares filter (ximgproc) smooths the disparity
  // along the left image's edges, and only pixels it is confident of (>= wls_min_confidence of 255) stay.
  std::string filter = "none";
  double wls_lambda = 8000.0;
  double wls_sigma_color = 1.5;
  double wls_min_confidence = 200.0;
  void validate() const;
};
// Rectified stereo pair (left, right: same size, 8-bit) to depth by OpenCV's semi-global matching, at
// 1/16 px of disparity (SGBM's sub-pixel fit), checked left-right and optionally filtered (above).
cv::Mat DepthFromStereo(const cv::Mat& left, const cv::Mat& right, double fx, double baseline_m,
                        const StereoParams& params = {});

// Sparse depth from a LiDAR scan: each point X_lidar is taken to the camera by
// P_camera_lidar (3x4, e.g. P2 * R_rect * Tr_velo_to_cam) and written at its pixel; the nearest point wins.
cv::Mat DepthFromLidar(const std::vector<Eigen::Vector4f>& points_lidar, const Eigen::Matrix<double, 3, 4>& P_camera_lidar,
                       int width, int height, double min_depth_m = 1.0);
// The same for points already in the camera's frame (projection K [I | 0]).
cv::Mat DepthFromCameraPoints(const std::vector<Eigen::Vector3f>& points_camera, const PinholeCamera& camera,
                              double min_depth_m = 1.0);

// Fills pixels without depth from the nearest valid depth within `radius_px` (box neighbourhood, the
// smallest depth wins so that foreground edges are not blurred into the background). For sparse LiDAR depth.
// With instance labels (CV_16UC1 or CV_32SC1, same size) and a spread above 0, a background pixel (label
// <= 0) is filled only where the depths in its neighbourhood agree: the farthest within (1 + spread) times
// the nearest. Across a depth edge the nearest depth belongs to what stands in front, and a static point
// given it sits too near the camera (which then seems to move less than it does). Object pixels are filled
// as without labels: the object is what stands in front.
cv::Mat FillSparseDepth(const cv::Mat& depth_m, int radius_px, const cv::Mat& labels = cv::Mat(),
                        double max_background_spread = 0.0);

}  // namespace dslam
