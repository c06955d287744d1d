#include "lidar/point_cloud_segmentation.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "lidar/pcl_module.h"

namespace dslam {

void LidarSegmentationParams::validate() const {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string("lidar_masks ") + name + " must be positive");
  };
  positive(max_range_m, "max_range_m");
  positive(ground_fit_range_m, "ground_fit_range_m");
  positive(ground_distance_m, "ground_distance_m");
  positive(max_height_above_ground_m, "max_height_above_ground_m");
  positive(cluster_tolerance_m, "cluster_tolerance_m");
  positive(min_object_height_m, "min_object_height_m");
  positive(max_object_length_m, "max_object_length_m");
  positive(max_object_base_height_m, "max_object_base_height_m");
  if (!(ground_max_tilt_deg > 0.0 && ground_max_tilt_deg < 45.0))
    throw std::invalid_argument("lidar_masks ground_max_tilt_deg must be in (0, 45)");
  if (min_cluster_points < 3) throw std::invalid_argument("lidar_masks min_cluster_points must be >= 3");
}

LidarSegmentation SegmentLidarObjects(const std::vector<Eigen::Vector3f>& points_camera,
                                      const LidarSegmentationParams& params, const std::vector<bool>& in_view) {
  params.validate();
  if (!in_view.empty() && in_view.size() != points_camera.size())
    throw std::invalid_argument("SegmentLidarObjects: in_view has " + std::to_string(in_view.size()) + " flags for " +
                                std::to_string(points_camera.size()) + " points");
  return Pcl().segment(points_camera, params, in_view);
}

}  // namespace dslam
