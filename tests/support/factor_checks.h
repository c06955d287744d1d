#pragma once
// Shared checks for factor tests: residual evaluation and Jacobians against central differences (on the
// pose manifold for pose blocks).

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "backend/factors/pose_block.h"

namespace dslam::test {

inline std::vector<double> Evaluate(const ceres::CostFunction& cost, const std::vector<double*>& params,
                                    std::vector<std::vector<double>>* jacobians = nullptr) {
  std::vector<double> residual(cost.num_residuals());
  std::vector<double*> jac_ptrs;
  if (jacobians) {
    jacobians->clear();
    for (int size : cost.parameter_block_sizes()) jacobians->emplace_back(cost.num_residuals() * size);
    for (auto& j : *jacobians) jac_ptrs.push_back(j.data());
  }
  EXPECT_TRUE(cost.Evaluate(params.data(), residual.data(), jacobians ? jac_ptrs.data() : nullptr));
  return residual;
}

// Compares the Jacobian of every parameter block with central differences: a point block (3) in its
// coordinates, a pose block (7) on the manifold, as Ceres uses it: J * PoseBlockPlusJacobian against
// differences along the tangent steps (q * Exp(phi), t + dt). (A cost function may hand over any
// ambient Jacobian with that product, e.g. one lifted from an analytic tangent Jacobian.)
inline void ExpectJacobiansMatchNumeric(const ceres::CostFunction& cost, const std::vector<double*>& params,
                                        double tolerance = 1e-6) {
  std::vector<std::vector<double>> analytic;
  Evaluate(cost, params, &analytic);
  const int num_residuals = cost.num_residuals();
  const double h = 1e-6;
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  for (size_t b = 0; b < params.size(); ++b) {
    const int size = cost.parameter_block_sizes()[b];
    const bool pose = size == kPoseBlockSize;
    const std::vector<double> saved(params[b], params[b] + size);
    Eigen::MatrixXd J = Eigen::Map<const RowMajor>(analytic[b].data(), num_residuals, size);
    if (pose) J = J * PoseBlockPlusJacobian(saved.data());
    for (int c = 0; c < J.cols(); ++c) {
      auto shifted = [&](double step) {
        if (pose) {
          Eigen::Matrix<double, 6, 1> delta = Eigen::Matrix<double, 6, 1>::Zero();
          delta[c] = step;
          PoseBlockPlus(saved.data(), delta, params[b]);
        } else {
          params[b][c] = saved[c] + step;
        }
        const auto r = Evaluate(cost, params);
        std::copy(saved.begin(), saved.end(), params[b]);
        return r;
      };
      const auto plus = shifted(h), minus = shifted(-h);
      for (int r = 0; r < num_residuals; ++r) {
        const double numeric = (plus[r] - minus[r]) / (2.0 * h);
        EXPECT_NEAR(J(r, c), numeric, tolerance * std::max(1.0, std::abs(numeric)))
            << "block " << b << (pose ? " tangent " : " parameter ") << c << " residual " << r;
      }
    }
  }
}

inline double MaxAbs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

inline PoseBlock ToBlock(const SE3& T) {
  PoseBlock block;
  PoseToBlock(T, block.data());
  return block;
}

// A generic, well-conditioned test pose.
inline SE3 SomePose(double scale = 1.0) {
  Vec6 xi;
  xi << 1.2, -0.4, 2.5, 0.3, -0.7, 0.2;
  return SE3::Exp(scale * xi);
}

inline Vec6 SmallTwist(double scale) {
  Vec6 xi;
  xi << 0.05, -0.08, 0.03, 0.02, 0.04, -0.03;
  return scale * xi;
}

// Solves with default options; returns whether Ceres found a usable solution.
inline bool Solve(ceres::Problem* problem) {
  ceres::Solver::Options options;
  ceres::Solver::Summary summary;
  ceres::Solve(options, problem, &summary);
  return summary.IsSolutionUsable();
}

}  // namespace dslam::test
