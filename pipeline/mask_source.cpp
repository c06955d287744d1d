#include "pipeline/mask_source.h"

#include <stdexcept>

#include "data/depth_maps.h"
#include "lidar/depth_scan.h"

namespace dslam {

void MaskSourceParams::validate() const {
  lidar.validate();
  if (!(lidar_depth_background_spread >= 0.0 && lidar_depth_background_spread <= 10.0))
    throw std::invalid_argument("masks.lidar_depth_background_spread must be in 0..10");
  if (depth_fill_radius_px < 0 || depth_fill_radius_px > 50)
    throw std::invalid_argument("the LiDAR depth fill radius must be in 0..50 px");
}

MaskSourceKind ParseMaskSource(const std::string& name) {
  if (name == "dataset") return MaskSourceKind::kDataset;
  if (name == "lidar_clusters") return MaskSourceKind::kLidarClusters;
  throw std::invalid_argument("unknown mask source '" + name + "' (expected dataset or lidar_clusters)");
}

std::string ToString(MaskSourceKind kind) { return kind == MaskSourceKind::kDataset ? "dataset" : "lidar_clusters"; }

void ApplyMaskSource(const MaskSourceParams& params, const PinholeCamera& camera, ImageFrame& frame) {
  if (params.source == MaskSourceKind::kDataset) return;
  const bool scan_recorded = !frame.lidar_points_camera.empty();
  if (!scan_recorded && params.lidar_from_depth && !frame.depth_m.empty()) {
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
  if (scan_recorded && params.lidar_depth_background_spread > 0.0)
    frame.depth_m = FillSparseDepth(DepthFromCameraPoints(frame.lidar_points_camera, camera), params.depth_fill_radius_px,
                                    frame.instance_ids, params.lidar_depth_background_spread);
}

}  // namespace dslam
