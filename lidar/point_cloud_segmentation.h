#pragma once
// Class-agnostic objects in one LiDAR scan: the ground plane is removed (RANSAC, a plane within a tilt of
// the camera's horizontal), the points above it up to a truck's height are clustered by Euclidean
// distance, and each cluster of an object's size and shape is kept: it stands on the ground and is shorter
// than a long vehicle. Points are in the camera frame (x right, y down,
// z forward). This is the only part of the mask source that includes PCL (lidar/ is its only user).

#include <vector>

#include <Eigen/Core>

namespace dslam {

struct LidarSegmentationParams {
  double max_range_m = 40.0;               // points farther (horizontally) are ignored
  double ground_fit_range_m = 30.0;        // the ground plane is fitted on points nearer than this
  double ground_distance_m = 0.25;         // a point this close to the plane is ground
  double ground_max_tilt_deg = 10.0;       // the plane's normal within this of the camera's vertical
  double max_height_above_ground_m = 4.5;  // higher points (bridges, crowns) are structure, never clustered
  double cluster_tolerance_m = 0.5;        // Euclidean clustering's neighbour distance
  int min_cluster_points = 40;
  double min_object_height_m = 0.6;        // lower clusters (kerbs, low walls) are not objects
  double max_object_length_m = 18.0;       // longer clusters (walls, buildings) are static structure
  // An object's lowest point is below this: it stands on the ground, or is seen above a nearer one (a
  // truck's front above a car's roof); higher clusters overhang (signs, crowns).
  double max_object_base_height_m = 2.0;
  void validate() const;
};

struct LidarObjectCluster {
  std::vector<int> point_indices;  // into the scan given to SegmentLidarObjects
  Eigen::Vector3f centroid_camera = Eigen::Vector3f::Zero();
  float top_height_m = 0.0f;  // of its highest point above the ground
  // Its footprint: the box of its points in the camera's x-z plane (x lo/hi, z lo/hi).
  Eigen::Vector2f footprint_lo = Eigen::Vector2f::Zero(), footprint_hi = Eigen::Vector2f::Zero();
  float footprintDiagonal() const { return (footprint_hi - footprint_lo).norm(); }
};

struct LidarSegmentation {
  std::vector<LidarObjectCluster> objects;  // nearest first
  std::vector<int> ground;                  // point indices on the ground plane
  // Ground plane n . p + d = 0 with n pointing up (n.y() < 0 in the camera frame); valid = false when
  // no plane was found (then no point is ground and heights are taken from the camera's own height).
  Eigen::Vector3f ground_normal = Eigen::Vector3f(0.0f, -1.0f, 0.0f);
  float ground_d = 1.65f;
  bool ground_valid = false;
  float heightAboveGround(const Eigen::Vector3f& p_camera) const { return ground_normal.dot(p_camera) + ground_d; }
};

// `in_view[i]` false excludes point i (outside the camera's field of view, say); empty: all points.
LidarSegmentation SegmentLidarObjects(const std::vector<Eigen::Vector3f>& points_camera,
                                      const LidarSegmentationParams& params, const std::vector<bool>& in_view = {});

}  // namespace dslam
