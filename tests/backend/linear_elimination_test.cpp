#include "backend/linear_elimination.h"

// Marginalisation of linear Gaussian factors, checked as a numerical analyst would: Schur complement and
// QR give the same Gaussian, and a fixed-lag smoother that marginalises with them gives, on a linear-
// Gaussian problem, the batch solution's estimate and covariance of what is still in its window.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <stdexcept>

namespace dslam {
namespace {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

MatX RandomMatrix(std::mt19937& rng, int rows, int cols) {
  std::normal_distribution<double> n(0.0, 1.0);
  MatX m(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) m(i, j) = n(rng);
  return m;
}

JacobianFactor RandomFactor(std::mt19937& rng, const std::vector<int>& keys, const std::map<int, int>& dims, int rows) {
  JacobianFactor f;
  f.keys = keys;
  for (int key : keys) f.blocks.push_back(RandomMatrix(rng, rows, dims.at(key)));
  f.residual = RandomMatrix(rng, rows, 1);
  return f;
}

// The normal equations of factors over `keys` (that order): H and b with cost 0.5 d^T H d + b^T d.
void NormalEquations(const std::vector<JacobianFactor>& factors, const std::vector<int>& keys,
                     const std::map<int, int>& dims, MatX* H, VecX* b) {
  std::map<int, int> offset;
  int n = 0;
  for (int key : keys) offset[key] = n, n += dims.at(key);
  *H = MatX::Zero(n, n);
  *b = VecX::Zero(n);
  for (const JacobianFactor& f : factors) {
    MatX A = MatX::Zero(f.residual.size(), n);
    for (size_t j = 0; j < f.keys.size(); ++j) A.middleCols(offset.at(f.keys[j]), dims.at(f.keys[j])) += f.blocks[j];
    *H += A.transpose() * A;
    *b += A.transpose() * f.residual;
  }
}

double MaxAbs(const MatX& m) { return m.size() ? m.cwiseAbs().maxCoeff() : 0.0; }

TEST(LinearElimination, SchurAndQrGiveTheSameGaussian) {
  std::mt19937 rng(3);
  const std::map<int, int> dims = {{0, 6}, {1, 6}, {2, 3}, {3, 3}, {4, 6}};
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<JacobianFactor> factors = {
        RandomFactor(rng, {0}, dims, 6),       RandomFactor(rng, {0, 1}, dims, 6), RandomFactor(rng, {0, 2}, dims, 3),
        RandomFactor(rng, {0, 2}, dims, 3),    RandomFactor(rng, {2, 4}, dims, 3), RandomFactor(rng, {1, 3}, dims, 3),
        RandomFactor(rng, {0, 3, 4}, dims, 6), RandomFactor(rng, {4}, dims, 2)};
    const GaussianMarginal schur = MarginaliseBySchur(factors, {0, 2});
    const GaussianMarginal qr = MarginaliseByQr(factors, {0, 2});
    ASSERT_EQ(schur.keys, (std::vector<int>{1, 3, 4}));
    ASSERT_EQ(qr.keys, schur.keys);
    ASSERT_EQ(schur.dims, (std::vector<int>{6, 3, 6}));
    EXPECT_LT(MaxAbs(schur.information - qr.information), 1e-9 * std::max(1.0, MaxAbs(schur.information)));
    EXPECT_LT(MaxAbs(schur.gradient - qr.gradient), 1e-9 * std::max(1.0, MaxAbs(schur.gradient)));
    // And both are the marginal of the joint Gaussian: its covariance block is the inverse of H.
    MatX H;
    VecX b;
    NormalEquations(factors, {0, 1, 2, 3, 4}, dims, &H, &b);
    const MatX joint_cov = H.inverse();
    std::vector<int> kept_rows;
    for (int r = 6; r < 12; ++r) kept_rows.push_back(r);
    for (int r = 15; r < 24; ++r) kept_rows.push_back(r);
    const MatX kept_cov = joint_cov(kept_rows, kept_rows);
    EXPECT_LT(MaxAbs(schur.information.inverse() - kept_cov), 1e-9 * std::max(1.0, MaxAbs(kept_cov)));
    const VecX joint_mean = -(H.ldlt().solve(b));
    const VecX kept_mean = -(schur.information.ldlt().solve(schur.gradient));
    EXPECT_LT(MaxAbs(kept_mean - joint_mean(kept_rows)), 1e-9 * std::max(1.0, MaxAbs(joint_mean)));
  }
}

TEST(LinearElimination, TheSquareRootRowsCarryTheSameInformation) {
  std::mt19937 rng(5);
  const std::map<int, int> dims = {{0, 6}, {1, 6}};
  const GaussianMarginal m = MarginaliseBySchur({RandomFactor(rng, {0, 1}, dims, 12)}, {});
  const SquareRootRows rows = SquareRootOf(m);
  ASSERT_EQ(rows.R.rows(), 12);
  EXPECT_LT(MaxAbs(rows.R.transpose() * rows.R - m.information), 1e-9 * MaxAbs(m.information));
  EXPECT_LT(MaxAbs(rows.R.transpose() * rows.r - m.gradient), 1e-9 * std::max(1.0, MaxAbs(m.gradient)));
  // A marginal that says nothing along some directions gives rows only for the others.
  const GaussianMarginal thin = MarginaliseBySchur({RandomFactor(rng, {0}, dims, 4)}, {});
  const SquareRootRows thin_rows = SquareRootOf(thin);
  EXPECT_EQ(thin_rows.R.rows(), 4);
  EXPECT_LT(MaxAbs(thin_rows.R.transpose() * thin_rows.R - thin.information), 1e-9 * MaxAbs(thin.information));
  const JacobianFactor f = FactorOf(m);
  ASSERT_EQ(f.keys, m.keys);
  MatX H;
  VecX b;
  NormalEquations({f}, {0, 1}, dims, &H, &b);
  EXPECT_LT(MaxAbs(H - m.information), 1e-9 * MaxAbs(m.information));
  EXPECT_LT(MaxAbs(b - m.gradient), 1e-9 * std::max(1.0, MaxAbs(m.gradient)));
}

TEST(LinearElimination, RefusesInconsistentFactorsAndUndeterminedVariables) {
  std::mt19937 rng(7);
  JacobianFactor a = RandomFactor(rng, {0}, {{0, 6}}, 6);
  JacobianFactor b = RandomFactor(rng, {0}, {{0, 3}}, 3);
  EXPECT_THROW(MarginaliseBySchur({a, b}, {0}), std::invalid_argument);  // key 0 with 6 and 3 columns
  JacobianFactor c = a;
  c.residual = VecX::Zero(5);
  EXPECT_THROW(MarginaliseByQr({c}, {0}), std::invalid_argument);  // 6 rows against 5 residuals
  JacobianFactor d = a;
  d.keys.push_back(1);
  EXPECT_THROW(MarginaliseBySchur({d}, {0}), std::invalid_argument);  // two keys, one block
  // Two rows cannot determine a 6-dimensional variable.
  const JacobianFactor thin = RandomFactor(rng, {0, 1}, {{0, 6}, {1, 6}}, 2);
  EXPECT_THROW(MarginaliseBySchur({thin}, {0}), std::runtime_error);
  EXPECT_THROW(MarginaliseByQr({thin}, {0}), std::runtime_error);
}

// A linear-Gaussian SLAM problem: poses x_k (3-dimensional) in a chain, each seeing the landmarks
// (2-dimensional) of a few frames around it through random linear measurement models. The fixed-lag
// smoother keeps the last W poses: when x_m leaves, it is eliminated with the landmarks it saw last, from
// every factor that touches them, and the Gaussian that remains replaces those factors.
TEST(LinearElimination, AFixedLagSmootherEqualsBatchOnALinearGaussianProblem) {
  std::mt19937 rng(11);
  constexpr int kFrames = 30, kWindow = 5, kLandmarks = 40;
  std::map<int, int> dims;
  auto pose = [](int k) { return k; };
  auto landmark = [](int j) { return 1000 + j; };
  for (int k = 0; k < kFrames; ++k) dims[pose(k)] = 3;
  for (int j = 0; j < kLandmarks; ++j) dims[landmark(j)] = 2;
  // Landmark j is seen from frames first_seen[j] .. first_seen[j] + 4 (fewer at the end).
  std::uniform_int_distribution<int> first(0, kFrames - 1);
  std::vector<int> first_seen(kLandmarks), last_seen(kLandmarks);
  for (int j = 0; j < kLandmarks; ++j) first_seen[j] = first(rng), last_seen[j] = std::min(kFrames - 1, first_seen[j] + 4);
  std::vector<std::vector<JacobianFactor>> frame_factors(kFrames);
  frame_factors[0].push_back(RandomFactor(rng, {pose(0)}, dims, 3));
  for (int k = 1; k < kFrames; ++k) frame_factors[k].push_back(RandomFactor(rng, {pose(k - 1), pose(k)}, dims, 3));
  for (int j = 0; j < kLandmarks; ++j)
    for (int k = first_seen[j]; k <= last_seen[j]; ++k) frame_factors[k].push_back(RandomFactor(rng, {pose(k), landmark(j)}, dims, 2));

  std::vector<JacobianFactor> all;
  for (const auto& f : frame_factors) all.insert(all.end(), f.begin(), f.end());

  std::vector<JacobianFactor> window;
  std::set<int> retired;
  for (int k = 0; k < kFrames; ++k) {
    window.insert(window.end(), frame_factors[k].begin(), frame_factors[k].end());
    const int m = k - kWindow;
    if (m < 0) continue;
    std::vector<int> leaving = {pose(m)};
    for (int j = 0; j < kLandmarks; ++j)
      if (last_seen[j] == m) leaving.push_back(landmark(j));
    std::vector<JacobianFactor> touching, rest;
    for (JacobianFactor& f : window) {
      const bool touches = std::any_of(f.keys.begin(), f.keys.end(),
                                       [&](int key) { return std::count(leaving.begin(), leaving.end(), key) > 0; });
      (touches ? touching : rest).push_back(std::move(f));
    }
    const GaussianMarginal marginal = (k % 2 == 0 ? MarginaliseBySchur : MarginaliseByQr)(touching, leaving);
    rest.push_back(FactorOf(marginal));
    window.swap(rest);
    retired.insert(leaving.begin(), leaving.end());
  }
  std::vector<int> all_keys, kept_keys;
  for (const auto& [key, dim] : dims) {
    all_keys.push_back(key);
    if (!retired.count(key)) kept_keys.push_back(key);
  }
  ASSERT_EQ(kept_keys.size(), static_cast<size_t>(kWindow) + kLandmarks - retired.size() + (kFrames - kWindow));

  MatX H_batch, H_window;
  VecX b_batch, b_window;
  NormalEquations(all, all_keys, dims, &H_batch, &b_batch);
  NormalEquations(window, kept_keys, dims, &H_window, &b_window);
  const MatX cov_batch = H_batch.inverse();
  const VecX mean_batch = -(H_batch.ldlt().solve(b_batch));
  const MatX cov_window = H_window.inverse();
  const VecX mean_window = -(H_window.ldlt().solve(b_window));
  std::vector<int> rows;
  int offset = 0;
  for (int key : all_keys) {
    if (!retired.count(key))
      for (int r = 0; r < dims.at(key); ++r) rows.push_back(offset + r);
    offset += dims.at(key);
  }
  EXPECT_LT(MaxAbs(mean_window - mean_batch(rows)), 1e-9 * std::max(1.0, MaxAbs(mean_batch)));
  EXPECT_LT(MaxAbs(cov_window - cov_batch(rows, rows)), 1e-9 * std::max(1.0, MaxAbs(cov_batch)));
}

}  // namespace
}  // namespace dslam
