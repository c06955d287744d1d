#include "pipeline/mask_source.h"

#include <stdexcept>

#include "lidar/depth_scan.h"

namespace dslam {

MaskSourceKind ParseMaskSource(const std::string& name) {
  if (name == "dataset") return MaskSourceKind::kDataset;
  if (name == "lidar_clusters") return MaskSourceKind::kLidarClusters;
  throw std::invalid_argument("unknown mask source '" + name + "' (expected dataset or lidar_clusters)");
}

std::string ToString(MaskSourceKind kind) { return kind == MaskSourceKind::kDataset ? "dataset" : "lidar_clusters"; }

void ApplyMaskSource(const MaskSourceParams& params, const PinholeCamera& camera, ImageFrame& frame) {
  if (params.source == MaskSourceKind::kDataset) return;
  if (frame.lidar_points_camera.empty() && params.lidar_from_depth && !frame.depth_m.empty()) {
    frame.lidar_points_camera = ScanFromDepth(frame.depth_m, camera);
    frame.lidar_origin_camera = Eigen::Vector3f::Zero();
    frame.lidar_up_camera = Eigen::Vector3f(0.0f, -1.0f, 0.0f);
  }
  if (frame.lidar_points_camera.empty())
    throw std::runtime_error("frame " + std::to_string(frame.frame_index) +
                             " has no LiDAR scan to make masks from (masks.source: lidar_clusters needs a "
                             "velodyne_points/ folder, a LiDAR topic, or masks.lidar_from_depth)");
  frame.instance_ids = LidarInstanceMask(frame.lidar_points_camera, frame.lidar_origin_camera, frame.lidar_up_camera, camera,
                                         params.lidar).ids;
}

}  // namespace dslam
