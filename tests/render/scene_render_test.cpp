// `dslam render-scene` on KITTI 0000 (shared data): the VDO-layout output reads back with the project's
// own readers, the written ground truth reprojects onto the masks, and the images carry enough texture
// to track features between consecutive frames.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <sstream>

#include "app/render_scene_command.h"
#include "data/dense_maps.h"
#include "data/image_codec.h"
#include "data/kitti_dataset.h"
#include "data/kitti_tracking.h"
#include "support/shared_data.h"
#include "support/no_display.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

namespace fs = std::filesystem;

class RenderScene : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(test::KittiTrackingDir() + "/label_02/0000.txt")) return;
    dir_ = new std::string(test::TempDir("render_scene"));
    RenderSceneOptions o;
    o.kitti_dir = test::KittiTrackingDir();
    o.sequence = "0000";
    o.frames = 6;
    o.stereo = true;
    o.out_dir = *dir_;
    o.quiet = true;
    std::ostringstream out, err;
    const test::ScopedNoDisplay headless;  // the project's own headless handling
    code_ = RunRenderSceneCommand(o, out, err);
    log_ = new std::string(out.str() + err.str());
  }
  static void TearDownTestSuite() {
    if (dir_) fs::remove_all(*dir_);
    delete dir_;
    delete log_;
  }
  void SetUp() override {
    if (!dir_) GTEST_SKIP() << "shared data absent: " << test::KittiTrackingDir();
    ASSERT_EQ(code_, 0) << *log_;
  }
  static std::string* dir_;
  static std::string* log_;
  static int code_;
};
std::string* RenderScene::dir_ = nullptr;
std::string* RenderScene::log_ = nullptr;
int RenderScene::code_ = -1;

// --stereo on a KITTI sequence: the right camera sits at the sequence's own baseline between its colour
// cameras ((P2 - P3) / fx in its calibration: 0.532 m on 0000, not the nominal 0.54 m).
TEST_F(RenderScene, TheStereoPairHasTheSequencesOwnBaseline) {
  const KittiCalibration kitti = ReadKittiCalibration(test::KittiTrackingDir() + "/calib/0000.txt");
  const double expected = (kitti.P[2](0, 3) - kitti.P[3](0, 3)) / kitti.fx();
  const KittiCalibration written = ReadKittiCalibration(*dir_ + "/calib.txt");
  EXPECT_NEAR((written.P[2](0, 3) - written.P[3](0, 3)) / written.fx(), expected, 1e-6);
  EXPECT_GT(std::abs(expected - 0.54), 0.005);
  for (int k = 0; k < 6; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "/image_1/%06d.png", k);
    EXPECT_TRUE(fs::exists(*dir_ + name)) << name;
  }
}

TEST_F(RenderScene, OutputReadsBackInTheVdoLayout) {
  const auto poses = ReadPoseGt(*dir_ + "/pose_gt.txt");
  ASSERT_EQ(poses.size(), 6u);
  const auto gt = LoadKittiGroundTruth(test::KittiTrackingDir(), "0000");
  for (size_t k = 0; k < poses.size(); ++k) EXPECT_TRUE(poses[k].isApprox(gt.T_world_camera[k], 1e-6)) << k;
  EXPECT_EQ(ReadTimes(*dir_ + "/times.txt").size(), 6u);
  const InstanceMask mask = ReadSemanticTxt(*dir_ + "/semantic/000003.txt");
  EXPECT_EQ(mask.width, 1242);
  EXPECT_EQ(mask.height, 375);
  const cv::Mat depth = dslam::ReadPngFile(*dir_ + "/depth/000003.png");
  ASSERT_EQ(depth.type(), CV_16UC1);
  const cv::Mat ids = dslam::ReadPngFile(*dir_ + "/mask/000003.png");
  ASSERT_EQ(ids.type(), CV_16UC1);
  for (int v = 0; v < mask.height; v += 11)
    for (int u = 0; u < mask.width; u += 13) EXPECT_EQ(ids.at<uint16_t>(v, u), mask.at(u, v));
  EXPECT_TRUE(fs::exists(*dir_ + "/image_0/000005.png"));
  EXPECT_TRUE(fs::exists(*dir_ + "/calib.txt"));
}

TEST_F(RenderScene, WrittenGroundTruthReprojectsOntoTheMask) {
  const auto rows = ReadObjectPoses(*dir_ + "/object_pose.txt");
  const auto gt = LoadKittiGroundTruth(test::KittiTrackingDir(), "0000");
  const auto calib = ReadKittiCalibration(*dir_ + "/calib.txt");
  ASSERT_GT(rows.size(), 10u);
  int hits = 0;
  for (const auto& r : rows) {
    const double h = gt.objects.at(r.object_id).h;
    const Vec3 c = r.bottom_centre_camera + Vec3(0.0, -h / 2.0, 0.0);  // box centre
    const int u = static_cast<int>(std::lround(calib.fx() * c.x() / c.z() + calib.cx()));
    const int v = static_cast<int>(std::lround(calib.fy() * c.y() / c.z() + calib.cy()));
    if (u < 0 || v < 0 || u >= 1242 || v >= 375) continue;
    const InstanceMask mask = ReadSemanticTxt(*dir_ + "/semantic/" + [&] {
      char buf[16];
      std::snprintf(buf, sizeof buf, "%06d.txt", r.frame);
      return std::string(buf);
    }());
    hits += mask.at(u, v) == r.object_id;
  }
  // Occluded centres aside, each written pose lands on its own object's pixels.
  EXPECT_GE(hits, static_cast<int>(0.7 * rows.size())) << hits << " of " << rows.size();
}

TEST_F(RenderScene, EnoughTextureToTrackFeaturesBetweenFrames) {
  cv::Mat a;
  cv::cvtColor(dslam::ReadPngFile(*dir_ + "/image_0/000002.png", dslam::ImageDecode::kColour), a, cv::COLOR_BGR2GRAY);
  cv::Mat b;
  cv::cvtColor(dslam::ReadPngFile(*dir_ + "/image_0/000003.png", dslam::ImageDecode::kColour), b, cv::COLOR_BGR2GRAY);
  ASSERT_FALSE(a.empty());
  std::vector<cv::Point2f> corners, forward, backward;
  cv::goodFeaturesToTrack(a, corners, 3000, 0.01, 7);
  std::vector<uchar> ok_f, ok_b;
  std::vector<float> e;
  cv::calcOpticalFlowPyrLK(a, b, corners, forward, ok_f, e);
  cv::calcOpticalFlowPyrLK(b, a, forward, backward, ok_b, e);
  int good = 0;
  for (size_t i = 0; i < corners.size(); ++i)
    good += ok_f[i] && ok_b[i] && cv::norm(corners[i] - backward[i]) < 1.0;
  std::cout << "features: " << corners.size() << " detected, " << good << " tracked forward-backward under 1 px\n";
  EXPECT_GE(good, 500);
}

TEST(RenderSceneCommand, RendersTheSimulatedCityAndRejectsBadArguments) {
  const std::string dir = test::TempDir("render_city");
  RenderSceneOptions o;
  o.scenario = "city";
  o.frames = 3;
  o.scale = 0.5;
  o.out_dir = dir;
  o.quiet = true;
  std::ostringstream out, err;
  const test::ScopedNoDisplay headless;
  ASSERT_EQ(RunRenderSceneCommand(o, out, err), 0) << err.str();
  const InstanceMask mask = ReadSemanticTxt(dir + "/semantic/000002.txt");
  EXPECT_EQ(mask.width, 621);
  std::set<int> ids(mask.ids.begin(), mask.ids.end());
  EXPECT_GE(ids.size(), 4u);  // background and several cars
  EXPECT_EQ(ReadPoseGt(dir + "/pose_gt.txt").size(), 3u);
  o.kitti_dir = "/tmp";  // both sources at once
  EXPECT_EQ(RunRenderSceneCommand(o, out, err), 2);
  o.kitti_dir.clear();
  o.scale = -1.0;
  EXPECT_EQ(RunRenderSceneCommand(o, out, err), 2);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dslam
