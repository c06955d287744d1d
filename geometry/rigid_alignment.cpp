#include "geometry/rigid_alignment.h"

#include <Eigen/SVD>
#include <random>

namespace dslam {

std::optional<SE3> AlignRigid(const std::vector<Vec3>& src, const std::vector<Vec3>& dst) {
  const size_t n = src.size();
  if (n < 3 || dst.size() != n) return std::nullopt;
  Vec3 mean_src = Vec3::Zero(), mean_dst = Vec3::Zero();
  for (size_t i = 0; i < n; ++i) {
    mean_src += src[i];
    mean_dst += dst[i];
  }
  mean_src /= static_cast<double>(n);
  mean_dst /= static_cast<double>(n);
  Mat3 cov = Mat3::Zero();
  for (size_t i = 0; i < n; ++i) cov += (dst[i] - mean_dst) * (src[i] - mean_src).transpose();
  Eigen::JacobiSVD<Mat3> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // Collinear or coincident points leave the rotation about their line undetermined.
  const auto& sv = svd.singularValues();
  if (sv(1) <= 1e-9 * std::max(1.0, sv(0))) return std::nullopt;
  Mat3 d = Mat3::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) d(2, 2) = -1.0;
  const Mat3 R = svd.matrixU() * d * svd.matrixV().transpose();
  return SE3(R, mean_dst - R * mean_src);
}

std::optional<RansacResult> AlignRigidRansac(const std::vector<Vec3>& src, const std::vector<Vec3>& dst,
                                             const RansacParams& params) {
  const int n = static_cast<int>(src.size());
  if (n < 3 || static_cast<int>(dst.size()) != n) return std::nullopt;
  const double threshold_sq = params.inlier_threshold_m * params.inlier_threshold_m;
  auto count_inliers = [&](const SE3& T, std::vector<bool>* mask) {
    int count = 0;
    for (int i = 0; i < n; ++i) {
      const bool inlier = (dst[i] - T * src[i]).squaredNorm() < threshold_sq;
      if (mask) (*mask)[i] = inlier;
      count += inlier;
    }
    return count;
  };

  std::mt19937_64 rng(params.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::optional<SE3> best;
  int best_count = -1;
  for (int it = 0; it < params.max_iterations; ++it) {
    int a = pick(rng), b = pick(rng), c = pick(rng);
    if (a == b || b == c || a == c) continue;
    const auto hypothesis = AlignRigid({src[a], src[b], src[c]}, {dst[a], dst[b], dst[c]});
    if (!hypothesis) continue;
    const int count = count_inliers(*hypothesis, nullptr);
    if (count > best_count) {
      best_count = count;
      best = hypothesis;
      if (count == n) break;
    }
  }
  if (!best || best_count < params.min_inliers) return std::nullopt;
  return RefineRigid(*best, src, dst, params);
}

std::optional<RansacResult> RefineRigid(const SE3& hypothesis, const std::vector<Vec3>& src, const std::vector<Vec3>& dst,
                                        const RansacParams& params) {
  const int n = static_cast<int>(src.size());
  if (static_cast<int>(dst.size()) != n) return std::nullopt;
  const double threshold_sq = params.inlier_threshold_m * params.inlier_threshold_m;
  RansacResult result;
  result.is_inlier.assign(n, false);
  auto count_inliers = [&](const SE3& T) {
    int count = 0;
    for (int i = 0; i < n; ++i) count += result.is_inlier[i] = (dst[i] - T * src[i]).squaredNorm() < threshold_sq;
    return count;
  };
  if (count_inliers(hypothesis) < params.min_inliers) return std::nullopt;
  std::vector<Vec3> src_in, dst_in;
  for (int i = 0; i < n; ++i) {
    if (!result.is_inlier[i]) continue;
    src_in.push_back(src[i]);
    dst_in.push_back(dst[i]);
  }
  result.transform = AlignRigid(src_in, dst_in).value_or(hypothesis);
  result.num_inliers = count_inliers(result.transform);
  if (result.num_inliers < params.min_inliers) return std::nullopt;
  return result;
}

}  // namespace dslam
