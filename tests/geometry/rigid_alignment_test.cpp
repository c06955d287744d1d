#include "geometry/rigid_alignment.h"

#include <gtest/gtest.h>

#include <random>

namespace dslam {
namespace {

std::vector<Vec3> Cloud(int n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i) pts.emplace_back(u(rng), u(rng), 10.0 + u(rng));
  return pts;
}

SE3 SomeMotion() { return SE3::Exp((Vec6() << 0.8, -0.1, 1.2, 0.02, 0.15, -0.01).finished()); }

TEST(AlignRigid, RecoversExactTransform) {
  const auto src = Cloud(20, 1);
  const SE3 T = SomeMotion();
  std::vector<Vec3> dst;
  for (const auto& p : src) dst.push_back(T * p);
  const auto fit = AlignRigid(src, dst);
  ASSERT_TRUE(fit);
  EXPECT_TRUE(fit->isApprox(T, 1e-9));
}

TEST(AlignRigid, RejectsDegenerateInput) {
  EXPECT_FALSE(AlignRigid({Vec3(0, 0, 1), Vec3(1, 0, 1)}, {Vec3(0, 0, 1), Vec3(1, 0, 1)}));
  // Collinear points leave the rotation about their line free.
  EXPECT_FALSE(AlignRigid({Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(2, 0, 1)}, {Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(2, 0, 1)}));
  EXPECT_FALSE(AlignRigid({Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(2, 1, 1)}, {Vec3(0, 0, 1)}));
}

TEST(AlignRigidRansac, RobustToTwentyPercentOutlierTracks) {
  const int n = 100;
  const auto src = Cloud(n, 2);
  const SE3 T = SomeMotion();
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::uniform_real_distribution<double> wild(-3.0, 3.0);
  std::vector<Vec3> dst;
  std::vector<bool> is_outlier(n, false);
  for (int i = 0; i < n; ++i) {
    Vec3 q = T * src[i] + Vec3(noise(rng), noise(rng), noise(rng));
    if (i % 5 == 0) {  // 20 %: tracks that jumped to another surface
      q += Vec3(wild(rng), wild(rng), wild(rng)).normalized() * 1.5;
      is_outlier[i] = true;
    }
    dst.push_back(q);
  }
  RansacParams params;
  params.inlier_threshold_m = 0.15;
  const auto fit = AlignRigidRansac(src, dst, params);
  ASSERT_TRUE(fit);
  EXPECT_LT((fit->transform.translation() - T.translation()).norm(), 0.02);
  EXPECT_LT((fit->transform.inverse() * T).angle(), 0.005);
  int wrong = 0;
  for (int i = 0; i < n; ++i) wrong += fit->is_inlier[i] == is_outlier[i];
  EXPECT_EQ(wrong, 0);
  // Plain least squares on the same data is visibly pulled off.
  const auto plain = AlignRigid(src, dst);
  ASSERT_TRUE(plain);
  EXPECT_GT((plain->translation() - T.translation()).norm(), 0.05);
}

TEST(RefineRigid, FromAnEarlierFitKeepsItsInliersRejectsTheRestAndRefits) {
  const int n = 40;
  const auto src = Cloud(n, 4);
  const SE3 T = SomeMotion();
  std::vector<Vec3> dst;
  for (int i = 0; i < n; ++i) dst.push_back(T * src[i] + (i < 5 ? Vec3(0.0, 0.0, 1.0) : Vec3::Zero()));
  RansacParams params;
  params.inlier_threshold_m = 0.15;
  // The hypothesis is a little off (an earlier fit on other data): the refit lands on T.
  const SE3 off = T * SE3::Exp((Vec6() << 0.03, 0.0, -0.02, 0.002, 0.0, 0.001).finished());
  const auto refined = RefineRigid(off, src, dst, params);
  ASSERT_TRUE(refined);
  EXPECT_TRUE(refined->transform.isApprox(T, 1e-9));
  EXPECT_EQ(refined->num_inliers, n - 5);
  for (int i = 0; i < n; ++i) EXPECT_EQ(refined->is_inlier[i], i >= 5) << i;
  // A hypothesis that explains too few pairs is no fit.
  params.min_inliers = n;
  EXPECT_FALSE(RefineRigid(T, src, dst, params));
  EXPECT_FALSE(RefineRigid(SE3(Eigen::Quaterniond::Identity(), Vec3(5.0, 0.0, 0.0)), src, dst, RansacParams{}));
}

TEST(AlignRigidRansac, DeterministicForSeed) {
  const auto src = Cloud(30, 4);
  std::vector<Vec3> dst;
  for (const auto& p : src) dst.push_back(SomeMotion() * p);
  dst[3] += Vec3(2, 0, 0);
  RansacParams params;
  const auto a = AlignRigidRansac(src, dst, params), b = AlignRigidRansac(src, dst, params);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->transform.matrix(), b->transform.matrix());
  EXPECT_EQ(a->num_inliers, 29);
}

TEST(AlignRigidRansac, FailsWithoutEnoughInliers) {
  const auto src = Cloud(6, 5);
  std::vector<Vec3> dst = Cloud(6, 6);  // unrelated
  RansacParams params;
  params.inlier_threshold_m = 0.01;
  params.min_inliers = 5;
  EXPECT_FALSE(AlignRigidRansac(src, dst, params));
}

}  // namespace
}  // namespace dslam
