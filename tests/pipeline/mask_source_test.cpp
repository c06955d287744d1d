#include "pipeline/mask_source.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "data/depth_maps.h"
#include "lidar/depth_scan.h"

namespace dslam {
namespace {

// A frame of a flat road (the camera 1.65 m above it) with a car-sized box 10 m ahead, as depth.
ImageFrame RoadWithACar(const PinholeCamera& camera) {
  ImageFrame frame;
  frame.frame_index = 7;
  frame.image = cv::Mat(camera.height, camera.width, CV_8UC3, cv::Scalar(90, 90, 90));
  frame.depth_m = cv::Mat(camera.height, camera.width, CV_32F, cv::Scalar(0.0f));
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const double y = (v - camera.cy) / camera.fy, x = (u - camera.cx) / camera.fx;
      double z = y > 1e-3 ? 1.65 / y : 0.0;  // the road
      // The box's rear face: x in [-0.9, 0.9] m, from the road up to 1.5 m, at z = 10 m.
      const double zb = 10.0;
      if (std::abs(x * zb) <= 0.9 && y * zb <= 1.65 && y * zb >= 0.15 && (z == 0.0 || z > zb)) z = zb;
      frame.depth_m.at<float>(v, u) = z > 0.0 && z < 80.0 ? static_cast<float>(z) : 0.0f;
    }
  return frame;
}

TEST(MaskSource, LidarClustersFromASampledScanMaskTheCarAndNothingElse) {
  const PinholeCamera camera;
  ImageFrame frame = RoadWithACar(camera);
  MaskSourceParams params;
  params.source = MaskSourceKind::kLidarClusters;
  params.lidar_from_depth = true;
  ApplyMaskSource(params, camera, frame);
  ASSERT_EQ(frame.instance_ids.type(), CV_32SC1);
  const cv::Mat car = frame.instance_ids == 1;
  EXPECT_GT(cv::countNonZero(car), 0);
  EXPECT_EQ(cv::countNonZero(frame.instance_ids > 1), 0) << "the road is no object";
  // The car's face spans x = +-0.9 m at 10 m: about 130 px around the principal point.
  const cv::Rect box = cv::boundingRect(car);
  EXPECT_NEAR(box.x + box.width / 2.0, camera.cx, 6.0);
  EXPECT_NEAR(box.width, 1.8 * camera.fx / 10.0, 12.0);
}

TEST(MaskSource, MasksFromARecordedScanRemakeTheDepthSoThatNoBackgroundPixelTakesTheCarsDepth) {
  const PinholeCamera camera;
  const ImageFrame exact = RoadWithACar(camera);
  ImageFrame frame = exact;
  frame.lidar_points_camera = ScanFromDepth(exact.depth_m, camera);  // a recorded scan: the depth is remade
  // As a dataset fills it: the nearest depth in the box.
  frame.depth_m = FillSparseDepth(DepthFromCameraPoints(frame.lidar_points_camera, camera), 6);
  MaskSourceParams params;
  params.source = MaskSourceKind::kLidarClusters;
  params.depth_fill_radius_px = 6;
  ImageFrame as_read = frame;
  params.lidar_depth_background_spread = 0.0;
  ApplyMaskSource(params, camera, as_read);
  EXPECT_EQ(cv::countNonZero(as_read.depth_m != frame.depth_m), 0) << "spread 0 leaves the depth as read";
  params.lidar_depth_background_spread = 0.1;
  ApplyMaskSource(params, camera, frame);
  // Background pixels given the car's depth (10 m) where the road behind it is farther than 11 m: the
  // box's depth bleeding onto the road beside and above it. The plain fill has some; the remade depth none.
  auto bled = [&](const ImageFrame& f) {
    int n = 0;
    for (int v = 0; v < camera.height; ++v)
      for (int u = 0; u < camera.width; ++u) {
        const float d = f.depth_m.at<float>(v, u), truth = exact.depth_m.at<float>(v, u);
        n += f.instance_ids.at<int>(v, u) == 0 && std::abs(d - 10.0f) < 0.01f && truth > 11.0f;
      }
    return n;
  };
  EXPECT_GT(bled(as_read), 100);
  EXPECT_EQ(bled(frame), 0);
  // The car keeps its depth.
  const cv::Mat car = frame.instance_ids > 0;
  EXPECT_GT(cv::countNonZero(car & (frame.depth_m > 9.5f) & (frame.depth_m < 10.5f)), 0.8 * cv::countNonZero(car & (exact.depth_m > 0.0f)));
}

TEST(MaskSource, TheDatasetsMasksStayAndAFrameWithoutAScanIsAClearError) {
  const PinholeCamera camera;
  ImageFrame frame = RoadWithACar(camera);
  frame.instance_ids = cv::Mat(camera.height, camera.width, CV_16U, cv::Scalar(3));
  ApplyMaskSource(MaskSourceParams{}, camera, frame);  // source: dataset
  EXPECT_EQ(cv::countNonZero(frame.instance_ids != 3), 0);
  MaskSourceParams lidar;
  lidar.source = MaskSourceKind::kLidarClusters;
  try {
    ApplyMaskSource(lidar, camera, frame);
    FAIL() << "made masks without a scan";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 7"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ParseMaskSource("lidar_clusters"), MaskSourceKind::kLidarClusters);
  EXPECT_EQ(ToString(ParseMaskSource("dataset")), "dataset");
  EXPECT_THROW(ParseMaskSource("maskrcnn"), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
