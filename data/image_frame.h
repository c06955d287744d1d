#pragma once
// One frame of image input as a camera driver and segmenter deliver it: the value the image front-end
// consumes, a packet between stages that no stage owns. OpenCV matrices share their pixels on copy;
// the front-end never writes into them.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <opencv2/core.hpp>

#include "data/frame_timing.h"
#include "data/measurements.h"

namespace dslam {

struct ImageFrame {
  int frame_index = 0;
  int64_t t_ns = 0;
  cv::Mat image;         // CV_8UC3 (BGR) or CV_8UC1
  cv::Mat depth_m;       // CV_32FC1 metres along z; 0 or non-finite = no depth
  cv::Mat instance_ids;  // CV_16UC1 or CV_32SC1; 0 (or negative) = background; empty = no segmentation
  cv::Mat flow_to_next;  // optional CV_32FC2 dense flow from this frame to the next, pixels
  std::optional<OdometryMeasurement> odometry;  // T_prev_curr; absent on the first frame or without odometry
  // The LiDAR scan taken with the image, in this camera's frame (metres), when the source has one; the
  // LiDAR's centre in the same frame. Masks from geometry (lidar/lidar_masks.h) are made from it.
  std::vector<Eigen::Vector3f> lidar_points_camera;
  Eigen::Vector3f lidar_origin_camera = Eigen::Vector3f::Zero();
  Eigen::Vector3f lidar_up_camera = Eigen::Vector3f(0.0f, -1.0f, 0.0f);  // the LiDAR's z axis (its elevations' zero)
  FrameTiming timing;  // when it passed each stage so far (online pipelines fill it in)
};

// Sets the frame's LiDAR scan from one recorded in the LiDAR's frame ("x y z reflectance") and the metric
// transform [R | t] from the LiDAR to this camera: the points, the LiDAR's centre and its up axis in the
// camera frame. One computation for every source (a dataset reader, a LiDAR topic), so that all give the
// same points.
void SetLidarScan(const std::vector<Eigen::Vector4f>& scan_lidar, const Eigen::Matrix<double, 3, 4>& T_camera_lidar,
                  ImageFrame* frame);

// Empty when the frame is usable; otherwise a message saying what is wrong (missing image, unsupported
// pixel type, sizes that differ between image, depth, mask and flow).
std::string FindInvalidImageFrame(const ImageFrame& frame);

// An 8-bit grey, BGR or BGRA image as 8-bit grey (grey is returned as it is, not copied).
cv::Mat GreyImage(const cv::Mat& image);

}  // namespace dslam
