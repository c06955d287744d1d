#include "simulation/shapes.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

TEST(Shapes, EllipsoidPointsLieOnItsSurfaceWithOutwardNormals) {
  const double a = 2.0, b = 1.0, c = 0.5;
  const auto points = SampleEllipsoid(a, b, c, 200);
  ASSERT_EQ(points.size(), 200u);
  Vec3 mean = Vec3::Zero();
  for (const SurfacePoint& s : points) {
    const Vec3& p = s.p_body;
    EXPECT_NEAR(p.x() * p.x() / (a * a) + p.y() * p.y() / (b * b) + p.z() * p.z() / (c * c), 1.0, 1e-9);
    EXPECT_NEAR(s.normal_body.norm(), 1.0, 1e-9);
    // The gradient of the implicit surface, normalised.
    const Vec3 gradient = Vec3(p.x() / (a * a), p.y() / (b * b), p.z() / (c * c)).normalized();
    EXPECT_TRUE(s.normal_body.isApprox(gradient, 1e-9));
    mean += p;
  }
  EXPECT_LT((mean / 200.0).norm(), 0.05);  // spread evenly: centred
}

TEST(Shapes, BoxFacesFollowKittisConventionAndSkipTheBottom) {
  const double l = 4.0, w = 2.0, h = 1.5;
  const auto points = SampleBox(l, w, h, 0.25);
  ASSERT_GT(points.size(), 100u);
  int top = 0;
  for (const SurfacePoint& s : points) {
    const Vec3& p = s.p_body;
    EXPECT_LE(std::abs(p.x()), l / 2 + 1e-9);
    EXPECT_LE(std::abs(p.z()), w / 2 + 1e-9);
    EXPECT_GE(p.y(), -h - 1e-9);  // height upwards is -y
    EXPECT_LE(p.y(), 1e-9);
    EXPECT_NEAR(s.normal_body.norm(), 1.0, 1e-12);
    EXPECT_FALSE(s.normal_body.isApprox(Vec3::UnitY(), 1e-9)) << "a bottom face point";
    // On the face its normal names.
    const double along = s.normal_body.dot(p);
    const double half = std::abs(s.normal_body.x()) > 0.5 ? l / 2 : std::abs(s.normal_body.z()) > 0.5 ? w / 2 : h;
    EXPECT_NEAR(along, half, 1e-9);
    top += s.normal_body.isApprox(-Vec3::UnitY(), 1e-9);
  }
  EXPECT_GT(top, 0);
}

}  // namespace
}  // namespace dslam
