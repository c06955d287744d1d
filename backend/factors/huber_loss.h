#pragma once
// Huber loss on a whitened residual's squared norm s, as Ceres' HuberLoss: rho(s) = s for s <= d^2,
// 2 d sqrt(s) - d^2 beyond. Shared by the fixed-lag solver and the marginalisation, so that a folded
// factor is weighted exactly as the solver weighted it.

#include <cmath>

namespace dslam {

struct HuberLoss {
  double delta;
  double rho(double s) const { return s <= delta * delta ? s : 2.0 * delta * std::sqrt(s) - delta * delta; }
  // rho'(s): the weight of iteratively reweighted least squares (Jacobians and residuals scale by its root).
  double weight(double s) const { return s <= delta * delta ? 1.0 : delta / std::sqrt(s); }
  double sqrtWeight(double s) const { return std::sqrt(weight(s)); }
};

}  // namespace dslam
