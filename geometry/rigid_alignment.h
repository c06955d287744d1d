#pragma once
// 3D-3D rigid registration: closed-form least squares (Kabsch / Umeyama without scale) and a
// RANSAC wrapper that rejects outlier correspondences.

#include <cstdint>
#include <optional>
#include <vector>

#include "geometry/se3.h"

namespace dslam {

// T minimising sum |dst_i - T * src_i|^2; nullopt when fewer than 3 pairs or degenerate (collinear).
std::optional<SE3> AlignRigid(const std::vector<Vec3>& src, const std::vector<Vec3>& dst);

struct RansacParams {
  int max_iterations = 200;
  double inlier_threshold_m = 0.15;  // residual |dst - T src| below which a pair is an inlier
  int min_inliers = 3;
  uint64_t seed = 1;  // the sampler is deterministic for a given seed
};

struct RansacResult {
  SE3 transform;
  std::vector<bool> is_inlier;  // one per input pair
  int num_inliers = 0;
};

// Samples minimal sets of 3 pairs, keeps the hypothesis with most inliers, refits on its inliers.
// nullopt when no hypothesis reaches params.min_inliers.
std::optional<RansacResult> AlignRigidRansac(const std::vector<Vec3>& src, const std::vector<Vec3>& dst,
                                             const RansacParams& params);

// RANSAC's last step from a given hypothesis (e.g. a fit made earlier on the same tracks): its inliers,
// the least-squares refit on them, and the refit's inliers. nullopt below params.min_inliers.
std::optional<RansacResult> RefineRigid(const SE3& hypothesis, const std::vector<Vec3>& src, const std::vector<Vec3>& dst,
                                        const RansacParams& params);

}  // namespace dslam
