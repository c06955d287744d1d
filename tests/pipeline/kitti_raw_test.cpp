// The front-end on real KITTI imagery from ../shared/data (skipped when it is absent): ten raw frames
// with LiDAR depth, and the VDO-SLAM flow and mask samples.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>

#include "data/dense_maps.h"
#include "data/image_dataset.h"
#include "frontend/flow_tracker.h"
#include "frontend/image_frontend.h"
#include "pipeline/config_yaml.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

const std::string kRaw = std::string(DSLAM_SHARED_DATA_DIR) + "/kitti_raw_2011_09_26_lead_car";
const std::string kSamples = std::string(DSLAM_SHARED_DATA_DIR) + "/kitti_tracking/samples";

TEST(KittiRawFrames, AtLeast300StaticTracksSurviveEachPairWithSubPixelConsistency) {
  if (!fs::is_directory(kRaw + "/image_02")) GTEST_SKIP() << "shared data absent: " << kRaw;
  // The shipped configuration for sparse LiDAR depth.
  const RunConfig config = LoadRunConfig(std::string(DSLAM_SOURCE_DIR) + "/config/kitti_raw_lidar.yaml");
  const ImageDataset data(kRaw, config.dataset);
  ASSERT_EQ(data.layout(), "kitti-raw");
  ASSERT_EQ(data.size(), 10);
  EXPECT_EQ(data.camera().width, 1242);
  ImageFrontend frontend(config.frontend, data.camera());
  frontend.process(data.read(0));
  for (int k = 1; k < data.size(); ++k) {
    const ImageFrame frame = data.read(k);
    const double valid_depth = cv::countNonZero(frame.depth_m) / static_cast<double>(frame.depth_m.total());
    const FrameMeasurement m = frontend.process(frame);
    const FrontendFrameStats& s = frontend.lastStats();
    std::cout << "frames " << k - 1 << "->" << k << ": " << s.static_tracked << " static tracks survive, median FB "
              << s.median_fb_error_px << " px, " << s.pnp_inliers << " PnP inliers, depth on "
              << 100.0 * valid_depth << " % of pixels" << std::endl;
    EXPECT_GE(s.static_tracked, 300) << k;
    EXPECT_LT(s.median_fb_error_px, 1.0) << k;
    EXPECT_TRUE(s.camera_from_pnp) << k;
    ASSERT_TRUE(m.camera_motion_guess);
    EXPECT_LT(m.camera_motion_guess->translation().norm(), 2.0) << k;  // stop-and-go traffic at 10 Hz
  }
}

TEST(KittiSamples, TheFloSampleDrivesThePrecomputedFlow) {
  const std::string path = kSamples + "/0000_flow_000000.flo";
  if (!fs::exists(path)) GTEST_SKIP() << "shared data absent: " << path;
  const FlowField f = ReadFlo(path);
  cv::Mat field(f.height, f.width, CV_32FC2);
  std::copy(f.uv.begin(), f.uv.end(), field.ptr<float>(0));
  FlowParams params;
  params.method = FlowMethod::kPrecomputed;
  FlowTracker tracker(params);
  const cv::Mat gray(f.height, f.width, CV_8UC1, cv::Scalar(0));
  const std::vector<cv::Point2f> points = {{100.0f, 200.0f}, {600.0f, 180.0f}, {1100.0f, 300.0f}};
  const FlowResult r = tracker.track(gray, gray, points, field);
  for (size_t i = 0; i < points.size(); ++i) {
    const int u = static_cast<int>(points[i].x), v = static_cast<int>(points[i].y);
    if (!r.ok[i]) continue;
    EXPECT_NEAR(r.points[i].x, points[i].x + f.u(u, v), 1e-3);
    EXPECT_NEAR(r.points[i].y, points[i].y + f.v(u, v), 1e-3);
  }
  EXPECT_GE(std::count(r.ok.begin(), r.ok.end(), 1), 2);
}

TEST(KittiSamples, ObjectPointsComeOnlyFromTheSemanticSampleMasks) {
  const std::string path = kSamples + "/0000_semantic_000101.txt";
  if (!fs::exists(path)) GTEST_SKIP() << "shared data absent: " << path;
  const InstanceMask mask = ReadSemanticTxt(path);
  ImageFrame frame;
  frame.instance_ids = cv::Mat(mask.height, mask.width, CV_32S);
  std::copy(mask.ids.begin(), mask.ids.end(), frame.instance_ids.ptr<int32_t>(0));
  frame.image = cv::Mat(mask.height, mask.width, CV_8UC1);
  cv::randu(frame.image, 0, 255);  // texture everywhere
  frame.depth_m = cv::Mat(mask.height, mask.width, CV_32FC1, cv::Scalar(10.0f));
  PinholeCamera camera;
  camera.width = mask.width, camera.height = mask.height;
  ImageFrontend frontend(FrontendParams{}, camera);
  const FrameMeasurement m = frontend.process(frame);
  ASSERT_FALSE(m.objects.empty());
  for (const auto& obj : m.objects)
    for (const auto& p : obj.points) {
      const Vec2 uv = camera.project(p.p_camera);
      EXPECT_EQ(mask.at(static_cast<int>(std::lround(uv.x())), static_cast<int>(std::lround(uv.y()))), obj.object_id);
    }
  for (const auto& p : m.static_points) {
    const Vec2 uv = camera.project(p.p_camera);
    EXPECT_LE(mask.at(static_cast<int>(std::lround(uv.x())), static_cast<int>(std::lround(uv.y()))), 0);
  }
}

}  // namespace
}  // namespace dslam
