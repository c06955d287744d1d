#include "render/rgbd_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "render/headless_display.h"
#include "render/sensor_noise.h"

namespace dslam {
namespace {

constexpr double kGroundY = 1.65;

class RgbdRendererTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::string error;
    display_ = new std::optional<HeadlessDisplay>(HeadlessDisplay::Acquire(&error));
    ASSERT_TRUE(display_->has_value()) << error;
  }
  static void TearDownTestSuite() { delete display_; }
  static std::optional<HeadlessDisplay>* display_;

  static std::vector<RenderQuad> Ground() {
    return {RenderQuad{{Vec3(-30, kGroundY, -5), Vec3(30, kGroundY, -5), Vec3(30, kGroundY, 150), Vec3(-30, kGroundY, 150)}, 3}};
  }
};
std::optional<HeadlessDisplay>* RgbdRendererTest::display_ = nullptr;

// Depth along the ray of pixel (u, v) where it meets the plane n . p = d (camera frame), or -1.
double RayPlaneDepth(const CameraIntrinsics& K, int u, int v, const Vec3& n, double d) {
  const Vec3 ray((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
  const double denom = n.dot(ray);
  return std::abs(denom) < 1e-9 ? -1.0 : d / denom;
}

TEST_F(RgbdRendererTest, DepthMatchesTheGeometryWithinOneCentimetre) {
  const CameraIntrinsics K;
  RgbdRenderer renderer(K, Ground());
  RenderBox box;
  box.object_id = 7;
  box.L_world_object = SE3(Eigen::AngleAxisd(0.3, Vec3::UnitY()).toRotationMatrix(), Vec3(1.0, kGroundY, 12.0));
  box.l = 4.0, box.w = 1.8, box.h = 1.5;
  const RgbdFrame f = renderer.render(SE3::Identity(), {box});
  ASSERT_EQ(f.width, K.width);
  // Road pixels (below the horizon, left of the box): the ray meets y = 1.65.
  int checked = 0;
  for (int v = 250; v < K.height; v += 20)
    for (int u = 20; u < 400; u += 60) {
      if (f.id(u, v) != 0) continue;
      EXPECT_NEAR(f.depth(u, v), RayPlaneDepth(K, u, v, Vec3::UnitY(), kGroundY), 0.01) << u << "," << v;
      ++checked;
    }
  EXPECT_GT(checked, 20);
  // Box faces: each face plane in the camera frame; pixels labelled 7 lie on one of the visible faces.
  const SE3& L = box.L_world_object;
  struct Face {
    Vec3 n_body;
    double offset;  // n . p = offset in the body frame
  };
  const Face faces[] = {{Vec3::UnitX(), 2.0}, {-Vec3::UnitX(), 2.0}, {Vec3::UnitZ(), 0.9}, {-Vec3::UnitZ(), 0.9},
                        {-Vec3::UnitY(), 1.5}};
  int box_pixels = 0;
  for (int v = 0; v < K.height; v += 7)
    for (int u = 0; u < K.width; u += 7) {
      if (f.id(u, v) != 7) continue;
      double best = 1e9;
      for (const auto& face : faces) {
        const Vec3 n = L.rotationMatrix() * face.n_body;
        const double d = face.offset + n.dot(L.translation());
        const double z = RayPlaneDepth(K, u, v, n, d);
        if (z > 0) best = std::min(best, std::abs(z - f.depth(u, v)));
      }
      EXPECT_LT(best, 0.01) << u << "," << v;
      ++box_pixels;
    }
  EXPECT_GT(box_pixels, 100);
}

TEST_F(RgbdRendererTest, MaskMatchesTheAnalyticProjectionOfTheBox) {
  const CameraIntrinsics K;
  RgbdRenderer renderer(K, {});
  RenderBox box;
  box.object_id = 300;  // needs both id bytes
  box.L_world_object = SE3(Eigen::AngleAxisd(-0.4, Vec3::UnitY()).toRotationMatrix(), Vec3(-2.0, kGroundY, 15.0));
  const RgbdFrame f = renderer.render(SE3::Identity(), {box});
  // Analytic mask: the convex hull of the eight projected corners (the box is fully in front).
  std::vector<Eigen::Vector2d> corners;
  for (double x : {-box.l / 2, box.l / 2})
    for (double y : {0.0, -box.h})
      for (double z : {-box.w / 2, box.w / 2}) {
        const Vec3 p = box.L_world_object * Vec3(x, y, z);
        corners.emplace_back(K.fx * p.x() / p.z() + K.cx, K.fy * p.y() / p.z() + K.cy);
      }
  std::sort(corners.begin(), corners.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  std::vector<Eigen::Vector2d> hull;  // monotone chain
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  for (int pass = 0; pass < 2; ++pass) {
    const size_t start = hull.size();
    for (const auto& p : corners) {
      while (hull.size() >= start + 2 && cross(hull[hull.size() - 2], hull.back(), p) <= 0) hull.pop_back();
      hull.push_back(p);
    }
    hull.pop_back();
    std::reverse(corners.begin(), corners.end());
  }
  long inter = 0, uni = 0, n_inside = 0, n_rendered = 0;
  Eigen::Vector2d sum_inside = Eigen::Vector2d::Zero(), sum_rendered = Eigen::Vector2d::Zero();
  for (int v = 0; v < K.height; ++v)
    for (int u = 0; u < K.width; ++u) {
      bool inside = true;
      for (size_t i = 0; i < hull.size() && inside; ++i)
        inside = cross(hull[i], hull[(i + 1) % hull.size()], Eigen::Vector2d(u, v)) >= 0;
      const bool rendered = f.id(u, v) == 300;
      inter += inside && rendered;
      uni += inside || rendered;
      if (inside) sum_inside += Eigen::Vector2d(u, v), ++n_inside;
      if (rendered) sum_rendered += Eigen::Vector2d(u, v), ++n_rendered;
    }
  ASSERT_GT(uni, 1000);
  EXPECT_GT(static_cast<double>(inter) / uni, 0.95) << inter << "/" << uni;
  // The principal point is right to a fraction of a pixel: the two masks share their centroid.
  const Eigen::Vector2d shift = sum_rendered / n_rendered - sum_inside / n_inside;
  EXPECT_LT(std::abs(shift.x()), 0.25) << shift.transpose();
  EXPECT_LT(std::abs(shift.y()), 0.25) << shift.transpose();
}

// render-scene --stereo: the right camera sits the baseline along the left one's x, so a surface at depth z
// appears fx * b / z pixels further left in the right image (KITTI's rectified pair).
TEST_F(RgbdRendererTest, AStereoPairsDisparityIsFocalTimesBaselineOverDepth) {
  const CameraIntrinsics K;
  RgbdRenderer renderer(K, {});
  constexpr double kBaselineM = 0.54;
  const SE3 T_left_right(Eigen::Quaterniond::Identity(), Vec3(kBaselineM, 0.0, 0.0));
  for (double z : {6.0, 12.0, 25.0}) {
    RenderBox box;
    box.object_id = 3;
    // Face-on: the box's end (its -x face after the rotation) faces the camera at depth z.
    box.L_world_object = SE3(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()).toRotationMatrix(), Vec3(0.0, 0.75, z + 2.0));
    const RgbdFrame left = renderer.render(SE3::Identity(), {box});
    const RgbdFrame right = renderer.render(T_left_right, {box});
    // The left edge of the box's mask on the row through the face's middle, sub-pixel by coverage.
    auto left_edge = [&](const RgbdFrame& f) {
      const int v = static_cast<int>(K.cy);
      for (int u = 0; u < f.width; ++u)
        if (f.id(u, v) == 3) return u;
      return -1;
    };
    const int u_left = left_edge(left), u_right = left_edge(right);
    ASSERT_GE(u_left, 0) << z;
    ASSERT_GE(u_right, 0) << z;
    EXPECT_NEAR(left.depth(u_left + 2, static_cast<int>(K.cy)), z, 0.01) << z;
    EXPECT_NEAR(u_left - u_right, K.fx * kBaselineM / z, 1.0) << "depth " << z;
  }
}

TEST_F(RgbdRendererTest, ColourIsTexturedAndDeterministic) {
  const CameraIntrinsics K;
  RgbdRenderer renderer(K, Ground());
  RenderBox box;
  box.L_world_object = SE3(Eigen::Quaterniond::Identity(), Vec3(0.0, kGroundY, 10.0));
  const RgbdFrame a = renderer.render(SE3::Identity(), {box});
  const RgbdFrame b = renderer.render(SE3::Identity(), {box});
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_EQ(a.instance, b.instance);
  // Texture: neighbouring pixels on the road differ often (no flat colour).
  int changes = 0;
  for (int u = 1; u < K.width; ++u) changes += std::abs(a.rgb[3 * (340 * K.width + u)] - a.rgb[3 * (340 * K.width + u - 1)]) > 8;
  EXPECT_GT(changes, 50);
  EXPECT_THROW(RgbdRenderer(CameraIntrinsics{0, 0}, {}), std::invalid_argument);
}

TEST(SensorNoise, DepthNoiseGrowsWithDepthAndHolesStayHoles) {
  RgbdFrame f;
  f.width = 1000, f.height = 2;
  f.rgb.assign(3 * 2000, 128);
  f.depth_m.assign(2000, 0.0f);
  for (int i = 0; i < 1000; ++i) f.depth_m[i] = 5.0f, f.depth_m[1000 + i] = 20.0f;
  f.depth_m[0] = 0.0f;
  const RgbdFrame clean = f;
  AddSensorNoise({2.0, 0.01, 0.001}, 7, &f);
  auto rms = [&](int from, int to) {
    double s = 0;
    for (int i = from; i < to; ++i) s += std::pow(f.depth_m[i] - clean.depth_m[i], 2);
    return std::sqrt(s / (to - from));
  };
  EXPECT_EQ(f.depth_m[0], 0.0f);
  EXPECT_NEAR(rms(1, 1000), 0.01 + 0.001 * 25, 0.006);
  EXPECT_NEAR(rms(1000, 2000), 0.01 + 0.001 * 400, 0.05);
  double image_rms = 0;
  for (size_t i = 0; i < f.rgb.size(); ++i) image_rms += std::pow(f.rgb[i] - 128.0, 2);
  EXPECT_NEAR(std::sqrt(image_rms / f.rgb.size()), 2.0, 0.3);
  RgbdFrame again = clean;
  AddSensorNoise({2.0, 0.01, 0.001}, 7, &again);
  EXPECT_EQ(again.depth_m, f.depth_m);  // seeded
}

}  // namespace
}  // namespace dslam
