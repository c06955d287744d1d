#pragma once
// The part of lidar/ that includes PCL, built as its own shared library (libdslam_pcl.so, loaded on first
// use: data/runtime_module.h) so that a process that never clusters or registers a scan starts without PCL's
// libraries. SegmentLidarObjects and RegisterPoints check their arguments and call these.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "data/runtime_module.h"
#include "lidar/point_cloud_segmentation.h"
#include "lidar/scan_registration.h"

namespace dslam {

// In the module (pcl_segmentation.cpp, pcl_registration.cpp); arguments already checked.
LidarSegmentation SegmentLidarObjectsWithPcl(const std::vector<Eigen::Vector3f>& points_camera,
                                             const LidarSegmentationParams& params, const std::vector<bool>& in_view);
Registration RegisterPointsWithPcl(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                                   const Eigen::Isometry3d& guess_target_source, const ScanRegistrationParams& params);

// What the module exports (pcl_module.cpp). Raise kVersion when a signature or a parameter struct changes.
struct PclFunctions {
  static constexpr int kVersion = 2;
  ModuleTableHeader header;
  decltype(&SegmentLidarObjectsWithPcl) segment = nullptr;
  decltype(&RegisterPointsWithPcl) register_points = nullptr;
};

inline const PclFunctions& Pcl() { return RuntimeModuleTable<PclFunctions>("dslam_pcl", "dslam_pcl_functions"); }

}  // namespace dslam

extern "C" const dslam::PclFunctions* dslam_pcl_functions();
