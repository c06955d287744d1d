#pragma once
// Rigid registration of two point sets (PCL's ICP family): consecutive LiDAR scans for the ego-motion, an
// object's points between scans for its motion. Points are in camera frames (metres).

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dslam {

enum class RegistrationMetric {
  kPointToPlane,  // each source point to the plane of its nearest target point's neighbours
  kGeneralized,   // generalized ICP (plane to plane)
  kPointToPoint,
};

struct ScanRegistrationParams {
  RegistrationMetric metric = RegistrationMetric::kPointToPlane;
  double voxel_m = 0.15;              // both sets thinned to one point per voxel first (0: not thinned)
  double max_correspondence_m = 1.0;  // pairs farther apart are not matched
  int max_iterations = 40;
  int normal_neighbours = 10;         // point to plane: each point's plane fitted to this many nearest points
  // Each iteration keeps this fraction of the matched pairs, the closest (trimmed ICP): points that moved
  // or have no counterpart in the other set then do not pull the motion. 1: every pair.
  double kept_pair_fraction = 1.0;
  void validate() const;
};

struct Registration {
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();  // p_target = T * p_source
  bool converged = false;
  double rms_m = 0.0;  // of the matched pairs at the end
};

// Throws std::invalid_argument when either set has fewer than 3 points.
Registration RegisterPoints(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                            const Eigen::Isometry3d& guess_target_source, const ScanRegistrationParams& params);

}  // namespace dslam
