#pragma once
// Inverse of a small symmetric positive definite matrix of fixed size, through its Cholesky factor.
//
// Why not Eigen::LLT<Matrix<double, N, N>>::solve(Identity): for a matrix right-hand side Eigen takes
// its general blocked triangular solver even at fixed size 3 or 9, which was the largest single cost of
// eliminating the fixed-lag smoother's point groups (about a tenth of a window solve). Loops with
// compile-time bounds are unrolled and cost a few hundred instructions.

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <cmath>

namespace dslam {

// A^-1 for symmetric positive definite A (its lower triangle is read). Returns false, leaving *inverse
// unspecified, when A is not positive definite to working precision.
template <int N>
bool InverseSpd(const Eigen::Matrix<double, N, N>& A, Eigen::Matrix<double, N, N>* inverse) {
  if constexpr (N == Eigen::Dynamic) {
    const Eigen::LLT<Eigen::MatrixXd> llt(A);
    if (llt.info() != Eigen::Success) return false;
    *inverse = llt.solve(Eigen::MatrixXd::Identity(A.rows(), A.cols()));
    return inverse->allFinite();  // LLT lets a NaN through
  } else {
    // A = L L^T, column by column.
    Eigen::Matrix<double, N, N> L = Eigen::Matrix<double, N, N>::Zero();
    for (int j = 0; j < N; ++j) {
      double d = A(j, j);
      for (int k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
      if (!(d > 0.0)) return false;
      L(j, j) = std::sqrt(d);
      const double inv = 1.0 / L(j, j);
      for (int i = j + 1; i < N; ++i) {
        double s = A(i, j);
        for (int k = 0; k < j; ++k) s -= L(i, k) * L(j, k);
        L(i, j) = s * inv;
      }
    }
    // M = L^-1 (lower triangular), by forward substitution on the identity's columns.
    Eigen::Matrix<double, N, N> M = Eigen::Matrix<double, N, N>::Zero();
    for (int j = 0; j < N; ++j) {
      M(j, j) = 1.0 / L(j, j);
      for (int i = j + 1; i < N; ++i) {
        double s = 0.0;
        for (int k = j; k < i; ++k) s -= L(i, k) * M(k, j);
        M(i, j) = s / L(i, i);
      }
    }
    // A^-1 = M^T M.
    inverse->noalias() = M.transpose().lazyProduct(M);
    return true;
  }
}

}  // namespace dslam
