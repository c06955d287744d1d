#include "lidar/lidar_masks.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "support/synthetic_lidar.h"

namespace dslam {
namespace {
using test::BoxOnGround;
using test::SceneBox;
const Eigen::Vector3f kUp(0.0f, -1.0f, 0.0f);  // the LiDAR level with the camera

// The exact silhouette of a box in the image (the convex hull of its projected corners).
cv::Mat Silhouette(const SceneBox& b, const PinholeCamera& camera) {
  std::vector<cv::Point> corners;
  for (int i = 0; i < 8; ++i) {
    const Vec3 c((i & 1 ? b.hi : b.lo).x(), (i & 2 ? b.hi : b.lo).y(), (i & 4 ? b.hi : b.lo).z());
    const Vec2 uv = camera.project(c);
    corners.emplace_back(cvRound(uv.x()), cvRound(uv.y()));
  }
  std::vector<cv::Point> hull;
  cv::convexHull(corners, hull);
  cv::Mat mask(camera.height, camera.width, CV_8U, cv::Scalar(0));
  cv::fillConvexPoly(mask, hull, cv::Scalar(255));
  return mask;
}

double IoU(const cv::Mat& a, const cv::Mat& b) {
  return static_cast<double>(cv::countNonZero(a & b)) / std::max(1, cv::countNonZero(a | b));
}

TEST(LidarMasks, EachObjectsMaskCoversItsSilhouetteWithIoUAbove0_8) {
  const PinholeCamera camera;  // KITTI's colour camera, 1242x375
  const SceneBox car = BoxOnGround(-2.5f, 12.0f, 1.8f, 1.5f, 4.2f), van = BoxOnGround(3.0f, 18.0f, 2.0f, 2.2f, 5.0f);
  const test::SyntheticLidar lidar;
  const LidarMaskResult r = LidarInstanceMask(lidar.scan({car, van}), lidar.origin, kUp, camera, LidarMaskParams{});
  ASSERT_EQ(r.segmentation.objects.size(), 2u);
  ASSERT_EQ(r.ids.type(), CV_32SC1);
  ASSERT_EQ(r.ids.size(), cv::Size(camera.width, camera.height));
  // Label 1 is the nearer (the car), 2 the van.
  const double iou_car = IoU(r.ids == 1, Silhouette(car, camera)), iou_van = IoU(r.ids == 2, Silhouette(van, camera));
  EXPECT_GT(iou_car, 0.8);
  EXPECT_GT(iou_van, 0.8);
  // Boxes follow the masks.
  EXPECT_EQ(r.boxes.size(), 2u);
  EXPECT_EQ(r.boxes[0], cv::boundingRect(r.ids == 1));
  // Nothing else is labelled: the ground stays background.
  EXPECT_EQ(cv::countNonZero(r.ids > 2), 0);
  EXPECT_LT(cv::countNonZero((r.ids > 0) & ~(Silhouette(car, camera) | Silhouette(van, camera))),
            0.25 * cv::countNonZero(r.ids > 0));
}

TEST(LidarMasks, ATruckCutByTheTopOfTheScanReachesUpToAVehiclesHeight) {
  const PinholeCamera camera;
  // 3.8 m tall, 6 m away: the top scan line (+2 degrees) meets it 2 m above the ground.
  const SceneBox truck = BoxOnGround(3.0f, 8.0f, 2.5f, 3.8f, 4.0f);
  const test::SyntheticLidar lidar;
  LidarMaskParams params;
  const LidarMaskResult extended = LidarInstanceMask(lidar.scan({truck}), lidar.origin, kUp, camera, params);
  ASSERT_EQ(extended.segmentation.objects.size(), 1u);
  EXPECT_LT(extended.segmentation.objects[0].top_height_m, 2.5f);  // what the LiDAR saw of it
  params.fov_top_margin_deg = 0.0;
  params.truncated_top_height_m = 1e-3;  // effectively no extension: compare with the scan's own extent
  const LidarMaskResult seen = LidarInstanceMask(lidar.scan({truck}), lidar.origin, kUp, camera, params);
  const cv::Mat exact = Silhouette(truck, camera);
  EXPECT_GT(IoU(extended.ids == 1, exact), IoU(seen.ids == 1, exact) + 0.1);
  EXPECT_GT(IoU(extended.ids == 1, exact), 0.75);
  EXPECT_LT(extended.boxes[0].y, seen.boxes[0].y - 20) << "the mask grew upwards";
}

TEST(LidarMasks, ANearerObjectKeepsThePixelsItHides) {
  const PinholeCamera camera;
  const SceneBox front = BoxOnGround(0.0f, 8.0f, 1.8f, 1.5f, 4.0f), behind = BoxOnGround(0.5f, 16.0f, 2.5f, 3.0f, 5.0f);
  const test::SyntheticLidar lidar;
  const LidarMaskResult r = LidarInstanceMask(lidar.scan({front, behind}), lidar.origin, kUp, camera, LidarMaskParams{});
  ASSERT_EQ(r.segmentation.objects.size(), 2u);
  const cv::Mat front_px = Silhouette(front, camera);
  // Inside the front car's silhouette (away from its edges), nothing is the car behind.
  cv::Mat inner;
  cv::erode(front_px, inner, cv::getStructuringElement(cv::MORPH_RECT, {9, 9}));
  EXPECT_EQ(cv::countNonZero((r.ids == 2) & inner), 0);
  EXPECT_GT(cv::countNonZero((r.ids == 1) & inner), 0.9 * cv::countNonZero(inner));
}

TEST(LidarMasks, AnEmptyScanGivesAnEmptyMaskAndBadParametersAreRefused) {
  const PinholeCamera camera;
  const LidarMaskResult r = LidarInstanceMask({}, Eigen::Vector3f::Zero(), kUp, camera, LidarMaskParams{});
  EXPECT_EQ(cv::countNonZero(r.ids), 0);
  EXPECT_TRUE(r.segmentation.objects.empty());
  LidarMaskParams p;
  p.grow_px = -1;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p = LidarMaskParams{};
  p.truncated_top_height_m = 0.0;
  EXPECT_THROW(p.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
