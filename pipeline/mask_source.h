#pragma once
// Where a run's instance masks come from: the dataset's own (mask files, or the mask topic in serve), or
// made from each frame's LiDAR scan by geometry (lidar/lidar_masks.h), with no network. Applied to every
// frame as it is read, before the front-end.

#include <string>

#include "data/image_frame.h"
#include "geometry/pinhole_camera.h"
#include "lidar/lidar_masks.h"

namespace dslam {

enum class MaskSourceKind { kDataset, kLidarClusters };
MaskSourceKind ParseMaskSource(const std::string& name);  // dataset | lidar_clusters; throws naming it
std::string ToString(MaskSourceKind kind);

struct MaskSourceParams {
  MaskSourceKind source = MaskSourceKind::kDataset;
  LidarMaskParams lidar;
  // A frame without a LiDAR scan gets one sampled from its depth image (lidar/depth_scan.h): to measure
  // the LiDAR mask source on rendered scenes, whose depth and masks are exact.
  bool lidar_from_depth = false;
  // Masks made from a recorded scan also remake the frame's depth from that scan, now that objects are
  // known: object pixels take the nearest return within depth_fill_radius_px (the object stands in front),
  // background pixels only where the returns around them agree within this fraction (data/depth_maps.h,
  // FillSparseDepth). 0 leaves the depth as the dataset made it.
  double lidar_depth_background_spread = 0.1;
  int depth_fill_radius_px = 2;  // dataset.lidar_fill_radius_px: MaskSourceOf (pipeline/run_config.h) sets it
  void validate() const;
};

// Replaces frame.instance_ids with masks from its LiDAR scan (kLidarClusters), and its depth as said
// above; leaves the frame as it is for kDataset. Throws std::runtime_error naming the frame when it has no scan to make masks from.
void ApplyMaskSource(const MaskSourceParams& params, const PinholeCamera& camera, ImageFrame& frame);

}  // namespace dslam
