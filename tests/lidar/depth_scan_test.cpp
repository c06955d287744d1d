#include "lidar/depth_scan.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

TEST(DepthScan, EachBeamReturnsTheDepthImagesPointWhereItMeetsTheImage) {
  const PinholeCamera camera;  // KITTI's colour camera, 1242x375
  // A wall 12 m ahead filling the image, and the lower rows a nearer wall at 6 m.
  cv::Mat depth(camera.height, camera.width, CV_32F, cv::Scalar(12.0f));
  depth.rowRange(300, camera.height).setTo(6.0f);
  const std::vector<Eigen::Vector3f> points = ScanFromDepth(depth, camera);
  ASSERT_GT(points.size(), 10000u);
  int near = 0;
  for (const Eigen::Vector3f& p : points) {
    ASSERT_TRUE(std::abs(p.z() - 12.0f) < 1e-3f || std::abs(p.z() - 6.0f) < 1e-3f) << p.transpose();
    // Each point lies on its pixel's ray: it projects back into the image.
    const Vec2 uv = camera.project(p.cast<double>());
    EXPECT_GE(uv.x(), -0.5);
    EXPECT_LT(uv.x(), camera.width - 0.5);
    near += p.z() < 7.0f;
  }
  EXPECT_GT(near, 0);
  // Beams above +2 degrees do not exist: nothing above the image row that +2 degrees reaches at the centre.
  for (const Eigen::Vector3f& p : points) EXPECT_LT(-p.y() / std::hypot(p.x(), p.z()), std::tan(2.2 * M_PI / 180.0));
}

TEST(DepthScan, NoDepthNoPointAndBadInputIsRefused) {
  const PinholeCamera camera;
  const cv::Mat none(camera.height, camera.width, CV_32F, cv::Scalar(0.0f));
  EXPECT_TRUE(ScanFromDepth(none, camera).empty());
  EXPECT_THROW(ScanFromDepth(cv::Mat(10, 10, CV_32F, cv::Scalar(1.0f)), camera), std::invalid_argument);
  EXPECT_THROW(ScanFromDepth(cv::Mat(camera.height, camera.width, CV_16U, cv::Scalar(1)), camera), std::invalid_argument);
  LidarBeamPattern pattern;
  pattern.azimuth_step_deg = 0.0;
  EXPECT_THROW(ScanFromDepth(none, camera, pattern), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
