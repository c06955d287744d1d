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

// Where each key's columns go: the leaving keys' first (in the order given), then the kept keys in increasing
// order. Checks that the factors agree on each key's dimension and that every block has its residual's rows.
struct Layout {
  std::map<int, int> column_of;
  int cols = 0, rows = 0, leaving_cols = 0;
  std::vector<int> kept_keys, kept_dims;
};

Layout LayoutOf(const std::vector<JacobianFactor>& factors, const std::vector<int>& leaving) {
  std::map<int, int> dim_of;
  Layout layout;
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
    layout.rows += static_cast<int>(f.residual.size());
  }
  for (int key : leaving) {
    const auto it = dim_of.find(key);
    if (it == dim_of.end() || layout.column_of.count(key)) continue;
    layout.column_of[key] = layout.cols;
    layout.cols += it->second;
  }
  layout.leaving_cols = layout.cols;
  for (const auto& [key, dim] : dim_of) {
    if (layout.column_of.count(key)) continue;
    layout.column_of[key] = layout.cols;
    layout.cols += dim;
    layout.kept_keys.push_back(key);
    layout.kept_dims.push_back(dim);
  }
  return layout;
}

// The stacked system [A_leaving | A_kept | r] of the factors, columns of the leaving keys first.
struct Stacked {
  Layout layout;
  MatX A;
  VecX r;
};

Stacked Stack(const std::vector<JacobianFactor>& factors, const std::vector<int>& leaving) {
  Stacked s{LayoutOf(factors, leaving), MatX(), VecX()};
  s.A = MatX::Zero(s.layout.rows, s.layout.cols);
  s.r.resize(s.layout.rows);
  int row = 0;
  for (const JacobianFactor& f : factors) {
    const auto n = f.residual.size();
    for (size_t j = 0; j < f.keys.size(); ++j)
      s.A.block(row, s.layout.column_of.at(f.keys[j]), n, f.blocks[j].cols()) += f.blocks[j];
    s.r.segment(row, n) = f.residual;
    row += static_cast<int>(n);
  }
  return s;
}

GaussianMarginal Empty(const Layout& layout) {
  GaussianMarginal m;
  m.keys = layout.kept_keys;
  m.dims = layout.kept_dims;
  const int n = layout.cols - layout.leaving_cols;
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
  const Layout layout = LayoutOf(factors, leaving);
  GaussianMarginal m = Empty(layout);
  const int nl = layout.leaving_cols, nk = m.dimension();
  // The normal equations factor by factor: a factor touches a few keys, so its blocks are small, where the
  // stacked Jacobian of a large prior would be rows x columns of mostly zeros.
  MatX H = MatX::Zero(layout.cols, layout.cols);
  VecX b = VecX::Zero(layout.cols);
  for (const JacobianFactor& f : factors) {
    for (size_t i = 0; i < f.keys.size(); ++i) {
      const int ci = layout.column_of.at(f.keys[i]);
      b.segment(ci, f.blocks[i].cols()).noalias() += f.blocks[i].transpose() * f.residual;
      for (size_t j = i; j < f.keys.size(); ++j) {
        const int cj = layout.column_of.at(f.keys[j]);
        const MatX block = f.blocks[i].transpose() * f.blocks[j];
        H.block(ci, cj, block.rows(), block.cols()) += block;
        if (j != i) H.block(cj, ci, block.cols(), block.rows()) += block.transpose();
      }
    }
  }
  if (nl == 0) {
    m.information = H;
    m.gradient = b;
    return m;
  }
  const Eigen::LLT<MatX> Hll(H.topLeftCorner(nl, nl));
  if (Hll.info() != Eigen::Success) throw std::runtime_error("marginalisation: the leaving variables are not determined");
  // H_kk - H_kl H_ll^-1 H_lk and b_k - H_kl H_ll^-1 b_l.
  const MatX Hll_inv_Hlk = Hll.solve(H.topRightCorner(nl, nk));
  m.information = H.bottomRightCorner(nk, nk);
  m.information.noalias() -= H.bottomLeftCorner(nk, nl) * Hll_inv_Hlk;
  m.information = 0.5 * (m.information + m.information.transpose());
  m.gradient = b.tail(nk) - Hll_inv_Hlk.transpose() * b.head(nl);
  return m;
}

GaussianMarginal MarginaliseByQr(const std::vector<JacobianFactor>& factors, const std::vector<int>& leaving) {
  const Stacked s = Stack(factors, leaving);
  GaussianMarginal m = Empty(s.layout);
  const int nl = s.layout.leaving_cols, nk = m.dimension();
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
  // Well determined (every pivot above the tolerance): the Cholesky factor, H = L L^T, R = L^T, r = L^-1 b,
  // an order of magnitude cheaper than the eigen-decomposition below.
  const Eigen::LLT<MatX> llt(marginal.information);
  if (llt.info() == Eigen::Success && marginal.information.rows() > 0) {
    const VecX pivots = llt.matrixL().toDenseMatrix().diagonal().cwiseAbs2();
    if (pivots.minCoeff() > relative_tolerance * marginal.information.diagonal().maxCoeff()) {
      SquareRootRows out;
      out.R = llt.matrixU();
      out.r = llt.matrixL().solve(marginal.gradient);
      return out;
    }
  }
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
