#include "output/frame_overlay.h"

#include <gtest/gtest.h>

#include <filesystem>


#include "data/image_codec.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

TEST(FrameOverlay, TintsTheMasksAndBoxesEachObjectByWhatIsReported) {
  const cv::Mat image(100, 200, CV_8UC3, cv::Scalar(100, 100, 100));
  cv::Mat ids(100, 200, CV_16U, cv::Scalar(0));
  ids(cv::Rect(20, 30, 40, 40)).setTo(1);
  ObjectMotionEstimate moving, standing, unboxed;
  moving.object_id = 7, moving.frame = 3, moving.is_dynamic = true, moving.speed_mps = 2.5;
  moving.image_box = ImageBox{20, 30, 40, 40};
  standing.object_id = 8, standing.is_dynamic = false;
  standing.image_box = ImageBox{120, 40, 50, 30};
  unboxed.object_id = 9;  // no box: not drawn
  const cv::Mat out = DrawObjectOverlay(image, ids, {moving, standing, unboxed});
  ASSERT_EQ(out.size(), image.size());
  ASSERT_EQ(out.type(), CV_8UC3);
  // Inside the mask (away from the box and its label) the grey is tinted; outside every box it is not.
  EXPECT_NE(out.at<cv::Vec3b>(50, 40), cv::Vec3b(100, 100, 100));
  EXPECT_EQ(out.at<cv::Vec3b>(90, 100), cv::Vec3b(100, 100, 100));
  // The moving object's box is green, the standing one's grey.
  const cv::Vec3b green = out.at<cv::Vec3b>(50, 20), grey = out.at<cv::Vec3b>(55, 120);
  EXPECT_GT(green[1], green[0] + 100);
  EXPECT_EQ(grey[0], grey[1]);
  EXPECT_GT(grey[0], 150);
  EXPECT_THROW(DrawObjectOverlay(image, cv::Mat(10, 10, CV_16U, cv::Scalar(0)), {}), std::invalid_argument);
  // A grey image is drawn in colour.
  EXPECT_EQ(DrawObjectOverlay(cv::Mat(100, 200, CV_8UC1, cv::Scalar(0)), cv::Mat(), {moving}).type(), CV_8UC3);
}

TEST(FrameOverlay, FramesAreSpreadAwayFromTheEndsAndWrittenWhole) {
  EXPECT_EQ(OverlayFrames(78, 4), (std::vector<int>{9, 29, 48, 68}));
  EXPECT_EQ(OverlayFrames(2, 4), (std::vector<int>{0, 1}));
  EXPECT_TRUE(OverlayFrames(0, 4).empty());
  const std::string dir = test::TempDir("overlay");
  const cv::Mat image(20, 30, CV_8UC3, cv::Scalar(1, 2, 3));
  WriteOverlayPng(image, dir + "/frame_000001.png");
  const cv::Mat back = dslam::ReadPngFile(dir + "/frame_000001.png", dslam::ImageDecode::kColour);
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(cv::norm(back, image, cv::NORM_INF), 0.0);
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find("partial"), std::string::npos);
  EXPECT_THROW(WriteOverlayPng(image, dir + "/no/such/folder/x.png"), std::runtime_error);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace dslam
