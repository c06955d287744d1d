#pragma once
// Instance masks from a LiDAR scan, no network: the scan's object clusters (lidar/point_cloud_segmentation.h)
// are projected into the image and grown to the object's pixels. Each point covers the gap to its
// neighbours in the scan (a few pixels across, more between scan lines); a z-buffer over every point,
// ground and structure included, keeps the nearest surface at each pixel, so an object grows only as far
// as its depth stays in front. A cluster cut by the top of the LiDAR's field of view (a truck beside the
// car) is extended up to a vehicle's height above the ground. Labels are 1..N in the order of the
// clusters (nearest first) and are not kept across frames: the front-end associates them
// (frontend.association.mask_ids_tracked: false).

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "geometry/pinhole_camera.h"
#include "lidar/point_cloud_segmentation.h"

namespace dslam {

struct LidarMaskParams {
  LidarSegmentationParams segmentation;
  int splat_half_width_px = 2;   // a point covers this far left and right (the scan's column spacing)
  int splat_half_height_px = 4;  // and up and down (half the spacing of the scan lines in the image)
  int grow_px = 3;               // each object's mask then grows this far into background pixels
  double fov_top_deg = 2.0;                // the LiDAR's highest beam above its horizontal (HDL-64E: +2)
  double fov_top_margin_deg = 0.3;         // a cluster reaching this close to it is cut (the beams are 0.33 apart)
  double truncated_top_height_m = 4.0;     // such a cluster's mask reaches up to this height above ground
  void validate() const;
};

struct LidarMaskResult {
  cv::Mat ids;                      // CV_32SC1, 0 = background, 1..N = objects
  LidarSegmentation segmentation;   // label l is segmentation.objects[l - 1]
  std::vector<cv::Rect> boxes;      // label l's box in the image, boxes[l - 1]; empty when it is not in view
};

// `lidar_origin_camera` and `lidar_up_camera`: the LiDAR's centre and its z axis in the camera frame
// (for the elevations of its beams).
LidarMaskResult LidarInstanceMask(const std::vector<Eigen::Vector3f>& points_camera,
                                  const Eigen::Vector3f& lidar_origin_camera, const Eigen::Vector3f& lidar_up_camera,
                                  const PinholeCamera& camera, const LidarMaskParams& params);

}  // namespace dslam
