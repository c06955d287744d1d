#include "backend/spd_inverse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace dslam {
namespace {

template <int N>
Eigen::Matrix<double, N, N> RandomSpd(int n, std::mt19937* rng) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = normal(*rng);
  // Well away from singular, but with a spread of scales as a point group's block has.
  Eigen::MatrixXd S = A * A.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
  for (int i = 0; i < n; ++i) S.row(i) *= std::pow(10.0, i % 3), S.col(i) *= std::pow(10.0, i % 3);
  return S;
}

template <int N>
void ExpectInverseOfRandomMatrices(int n) {
  std::mt19937 rng(7 + n);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Matrix<double, N, N> A = RandomSpd<N>(n, &rng);
    Eigen::Matrix<double, N, N> inverse;
    ASSERT_TRUE(InverseSpd<N>(A, &inverse));
    const Eigen::MatrixXd product = Eigen::MatrixXd(A) * Eigen::MatrixXd(inverse);
    EXPECT_LT((product - Eigen::MatrixXd::Identity(n, n)).norm(), 1e-9) << "size " << n << ", trial " << trial;
    EXPECT_LT((inverse - inverse.transpose()).norm(), 1e-12 * inverse.norm());
  }
}

TEST(InverseSpd, InvertsSymmetricPositiveDefiniteMatricesOfEveryGroupSize) {
  ExpectInverseOfRandomMatrices<3>(3);
  ExpectInverseOfRandomMatrices<6>(6);
  ExpectInverseOfRandomMatrices<9>(9);
  ExpectInverseOfRandomMatrices<12>(12);
  ExpectInverseOfRandomMatrices<Eigen::Dynamic>(15);
}

TEST(InverseSpd, RefusesAMatrixThatIsNotPositiveDefinite) {
  Eigen::Matrix3d semidefinite = Eigen::Matrix3d::Zero();
  semidefinite(0, 0) = 1.0;
  semidefinite(1, 1) = 1.0;  // no information on the third axis
  Eigen::Matrix3d inverse;
  EXPECT_FALSE(InverseSpd<3>(semidefinite, &inverse));
  Eigen::Matrix<double, 6, 6> indefinite = Eigen::Matrix<double, 6, 6>::Identity();
  indefinite(4, 4) = -2.0;
  Eigen::Matrix<double, 6, 6> inverse6;
  EXPECT_FALSE(InverseSpd<6>(indefinite, &inverse6));
  Eigen::MatrixXd nan = Eigen::MatrixXd::Identity(15, 15);
  nan(3, 3) = std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd inverse15;
  EXPECT_FALSE(InverseSpd<Eigen::Dynamic>(nan, &inverse15));
  Eigen::Matrix3d nan3 = Eigen::Matrix3d::Identity();
  nan3(2, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(InverseSpd<3>(nan3, &inverse));
}

}  // namespace
}  // namespace dslam
