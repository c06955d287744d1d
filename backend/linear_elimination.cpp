#include "backend/linear_elimination.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace dslam {
namespace {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

// The stacked system [A_leaving | A_kept | r] of the factors, columns of the leaving keys first.
struct Stacked {
  MatX A;
  VecX r;
  int leaving_cols = 0;
  std::vector<int> kept_keys, kept_dims;
};

Stacked Stack(const std::vector<JacobianFactor>& factors, const std::vector<int>& leaving) {
  std::map<int, int> dim_of;
  int rows = 0;
  for (const JacobianFactor& f : factors) {
    if (f.keys.size() != f.blocks.size())
      throw std::invalid_argument("linear factor: " + std::to_string(f.keys.size()) + " keys but " +
                                  std::to_string(f.blocks.size()) + " blocks");
    for (size_t j = 0; j < f.keys.size(); ++j) {
      if (f.blocks[j].rows() != f.residual.size())
        throw std::invalid_argument("linear factor: a block of key " + std::to_string(f.keys[j]) + " has " +
                                    std::to_string(f.blocks[j].rows()) + " rows, its residual " +
                                    std::to_string(f.residual.size()));
      const auto [it, is_new] = dim_of.try_emplace(f.keys[j], static_cast<int>(f.blocks[j].cols()));
      if (!is_new && it->second != f.blocks[j].cols())
        throw std::invalid_argument("linear factor: key " + std::to_string(f.keys[j]) + " has blocks of " +
                                    std::to_string(it->second) + " and " + std::to_string(f.blocks[j].cols()) +
                                    " columns");
    }
    rows += static_cast<int>(f.residual.size());
  }
  Stacked s;
  std::map<int, int> column_of;
  int cols = 0;
  for (int key : leaving) {
    const auto it = dim_of.find(key);
    if (it == dim_of.end() || column_of.count(key)) continue;
    column_of[key] = cols;
    cols += it->second;
  }
  s.leaving_cols = cols;
  for (const auto& [key, dim] : dim_of) {
    if (column_of.count(key)) continue;
    column_of[key] = cols;
    cols += dim;
    s.kept_keys.push_back(key);
    s.kept_dims.push_back(dim);
  }
  s.A = MatX::Zero(rows, cols);
  s.r.resize(rows);
  int row = 0;
  for (const JacobianFactor& f : factors) {
    const auto n = f.residual.size();
    for (size_t j = 0; j < f.keys.size(); ++j)
      s.A.block(row, column_of.at(f.keys[j]), n, f.blocks[j].cols()) += f.blocks[j];
    s.r.segment(row, n) = f.residual;
    row += static_cast<int>(n);
  }
  return s;
}

GaussianMarginal Empty(const Stacked& s) {
  GaussianMarginal m;
  m.keys = s.kept_keys;
  m.dims = s.kept_dims;
  const int n = static_cast<int>(s.A.cols()) - s.leaving_cols;
  m.information = MatX::Zero(n, n);
  m.gradient = VecX::Zero(n);
  return m;
}

}  // namespace

int GaussianMarginal::dimension() const { return static_cast<int>(gradient.size()); }

int GaussianMarginal::offset(int key) const {
  int row = 0;
  for (size_t i = 0; i < keys.size(); ++i) {
    if (keys[i] == key) return row;
    row += dims[i];
  }
  return -1;
}

GaussianMarginal MarginaliseBySchur(const std::vector<JacobianFactor>& factors, const std::vector<int>& leaving) {
  const Stacked s = Stack(factors, leaving);
  GaussianMarginal m = Empty(s);
  const int nl = s.leaving_cols, nk = m.dimension();
  const MatX H = s.A.transpose() * s.A;
  const VecX b = s.A.transpose() * s.r;
  if (nl == 0) {
    m.information = H;
    m.gradient = b;
    return m;
  }
  const Eigen::LLT<MatX> Hll(H.topLeftCorner(nl, nl));
  if (Hll.info() != Eigen::Success) throw std::runtime_error("marginalisation: the leaving variables are not determined");
  // H_kk - H_kl H_ll^-1 H_lk and b_k - H_kl H_ll^-1 b_l.
  const MatX Hll_inv_Hlk = Hll.solve(H.topRightCorner(nl, nk));
  m.information = H.bottomRightCorner(nk, nk) - H.bottomLeftCorner(nk, nl) * Hll_inv_Hlk;
  m.information = 0.5 * (m.information + m.information.transpose());
  m.gradient = b.tail(nk) - Hll_inv_Hlk.transpose() * b.head(nl);
  return m;
}

GaussianMarginal MarginaliseByQr(const std::vector<JacobianFactor>& factors, const std::vector<int>& leaving) {
  const Stacked s = Stack(factors, leaving);
  GaussianMarginal m = Empty(s);
  const int nl = s.leaving_cols, nk = m.dimension();
  MatX rest(s.A.rows(), nk + 1);
  rest << s.A.rightCols(nk), s.r;
  if (nl > 0) {
    // Q^T rotates the leaving columns onto their first nl rows; the rows below involve only the kept
    // variables and are the marginal's square root, exactly.
    const Eigen::ColPivHouseholderQR<MatX> qr(s.A.leftCols(nl));
    if (qr.rank() < nl) throw std::runtime_error("marginalisation: the leaving variables are not determined");
    rest = (qr.householderQ().transpose() * rest).eval().bottomRows(s.A.rows() - nl);
  }
  m.information = rest.leftCols(nk).transpose() * rest.leftCols(nk);
  m.gradient = rest.leftCols(nk).transpose() * rest.col(nk);
  return m;
}

SquareRootRows SquareRootOf(const GaussianMarginal& marginal, double relative_tolerance) {
  const Eigen::SelfAdjointEigenSolver<MatX> eig(marginal.information);
  const VecX& lambda = eig.eigenvalues();  // increasing
  const int n = static_cast<int>(lambda.size());
  const double floor = n > 0 ? std::max(lambda[n - 1], 0.0) * relative_tolerance : 0.0;
  std::vector<int> kept;
  for (int i = 0; i < n; ++i)
    if (lambda[i] > floor && lambda[i] > 0.0) kept.push_back(i);
  SquareRootRows out;
  out.R.resize(static_cast<Eigen::Index>(kept.size()), n);
  out.r.resize(static_cast<Eigen::Index>(kept.size()));
  for (size_t j = 0; j < kept.size(); ++j) {
    const double s = std::sqrt(lambda[kept[j]]);
    const auto v = eig.eigenvectors().col(kept[j]);
    out.R.row(static_cast<Eigen::Index>(j)) = s * v.transpose();
    out.r[static_cast<Eigen::Index>(j)] = v.dot(marginal.gradient) / s;
  }
  return out;
}

JacobianFactor FactorOf(const GaussianMarginal& marginal) {
  const SquareRootRows rows = SquareRootOf(marginal);
  JacobianFactor f;
  f.keys = marginal.keys;
  f.residual = rows.r;
  int col = 0;
  for (int dim : marginal.dims) {
    f.blocks.push_back(rows.R.middleCols(col, dim));
    col += dim;
  }
  return f;
}

}  // namespace dslam
