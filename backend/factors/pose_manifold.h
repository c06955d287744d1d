#pragma once
// The manifold of a pose block (pose_block.h): Eigen's quaternion manifold times R^3, in the block's layout.

#include <ceres/manifold.h>
#include <ceres/product_manifold.h>

namespace dslam {

inline ceres::Manifold* NewPoseManifold() {
  return new ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>();
}

}  // namespace dslam
