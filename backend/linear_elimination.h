#pragma once
// Marginalisation of linear(ised) Gaussian factors: the leaving variables are eliminated from the
// factors that touch them, by the Schur complement of their normal equations or by a QR factorisation
// of the stacked Jacobians, and what remains is one dense Gaussian on the variables they were tied to
// (their Markov blanket). Both give the same Gaussian; QR never squares the condition number.
//
// A factor is whitened rows r(d) = r + sum_j A_j d_j over variables named by integer keys, d_j the
// tangent step of variable j from the point the rows were linearised at.

#include <Eigen/Core>

#include <vector>

namespace dslam {

struct JacobianFactor {
  std::vector<int> keys;
  std::vector<Eigen::MatrixXd> blocks;  // rows x (the key's tangent dimension), one per key
  Eigen::VectorXd residual;             // rows
};

// A Gaussian on `keys` (that order, those dimensions) in information form: the cost of a step d is
// 0.5 d^T H d + b^T d + constant, so its minimum is at H d = -b and its covariance is H^-1.
struct GaussianMarginal {
  std::vector<int> keys;
  std::vector<int> dims;
  Eigen::MatrixXd information;  // H
  Eigen::VectorXd gradient;     // b

  int dimension() const;
  // First row of `key` in H, -1 when the marginal does not involve it.
  int offset(int key) const;
};

// Rows R d + r of a marginal with R^T R = H and R^T r = b: H's Cholesky factor when every pivot is above
// relative_tolerance times H's largest diagonal entry, else from H's eigen-decomposition, where directions
// whose information is below relative_tolerance times the largest carry none and are left out, so a
// rank-deficient marginal gives fewer rows than its dimension.
struct SquareRootRows {
  Eigen::MatrixXd R;
  Eigen::VectorXd r;
};
SquareRootRows SquareRootOf(const GaussianMarginal& marginal, double relative_tolerance = 1e-12);

// The Gaussian on every key of `factors` that is not in `leaving`, in increasing key order, with the
// leaving keys eliminated. Throws std::invalid_argument when a key's blocks disagree on its dimension or a
// block's rows differ from its residual's, and std::runtime_error when the leaving variables are not
// determined by the factors (their block is singular).
GaussianMarginal MarginaliseBySchur(const std::vector<JacobianFactor>& factors, const std::vector<int>& leaving);
GaussianMarginal MarginaliseByQr(const std::vector<JacobianFactor>& factors, const std::vector<int>& leaving);

// The factor that a marginal is, as rows on its keys (SquareRootOf): what a prior contributes to the next
// elimination.
JacobianFactor FactorOf(const GaussianMarginal& marginal);

}  // namespace dslam
