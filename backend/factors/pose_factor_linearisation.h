#pragma once
// A 6-dimensional pose factor (odometry, pose prior, motion smoothness: the templated functors Ceres'
// batch solver differentiates) linearised for the solvers that work in the tangent: its residual and its
// Jacobians in the tangents [dt; phi] of its blocks, Ceres' Jacobian in a block's seven coordinates
// times the manifold's Plus Jacobian.

#include <ceres/cost_function.h>

#include "backend/factors/pose_block.h"

namespace dslam {

// `blocks` has one entry per parameter block of `cost`; J (when not null) one entry per block, null for
// a block whose Jacobian is not wanted (held constant).
inline Vec6 LinearisePoseFactor(const ceres::CostFunction& cost, const double* const* blocks, Mat6* const* J) {
  const int num_blocks = static_cast<int>(cost.parameter_block_sizes().size());
  Eigen::Matrix<double, 6, 7, Eigen::RowMajor> ambient[2];
  double* jacobians[2] = {nullptr, nullptr};
  bool any = false;
  for (int i = 0; i < num_blocks && J; ++i)
    if (J[i]) jacobians[i] = ambient[i].data(), any = true;
  Vec6 r;
  cost.Evaluate(blocks, r.data(), any ? jacobians : nullptr);
  for (int i = 0; i < num_blocks && any; ++i)
    if (J[i]) *J[i] = ambient[i] * PoseBlockPlusJacobian(blocks[i]);
  return r;
}

}  // namespace dslam
