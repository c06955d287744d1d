#include "plugin/image_message.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

TEST(ImageMessage, RoundTripsColourDepthAndMasks) {
  cv::Mat colour(5, 7, CV_8UC3);
  cv::randu(colour, 0, 255);
  const auto c = DecodeImage(EncodeImage(colour, ImageRole::kColour, 123456789012LL, "camera"), ImageRole::kColour);
  ASSERT_EQ(c.error, "");
  EXPECT_EQ(cv::norm(c.image, colour, cv::NORM_INF), 0.0);

  cv::Mat depth(5, 7, CV_32FC1, cv::Scalar(12.25f));
  depth.at<float>(2, 3) = std::nanf("");
  const auto d = DecodeImage(EncodeImage(depth, ImageRole::kDepth, 1, "camera"), ImageRole::kDepth);
  ASSERT_EQ(d.error, "");
  EXPECT_FLOAT_EQ(d.image.at<float>(0, 0), 12.25f);
  EXPECT_FLOAT_EQ(d.image.at<float>(2, 3), 0.0f);  // NaN depth means no depth

  cv::Mat ids(5, 7, CV_16UC1, cv::Scalar(0));
  ids.at<uint16_t>(1, 1) = 4242;
  const auto m = DecodeImage(EncodeImage(ids, ImageRole::kMask, 1, "camera"), ImageRole::kMask);
  ASSERT_EQ(m.error, "");
  EXPECT_EQ(m.image.at<uint16_t>(1, 1), 4242);

  EXPECT_EQ(StampToNs(NsToStamp(123456789012LL)), 123456789012LL);
}

TEST(ImageMessage, MaskIdsAbove65535TravelAsThirtyTwoBitsAndStayApart) {
  cv::Mat ids(4, 6, CV_32SC1, cv::Scalar(0));
  ids.at<int32_t>(0, 0) = 65535, ids.at<int32_t>(1, 1) = 70000, ids.at<int32_t>(2, 2) = 70001;
  ids.at<int32_t>(3, 3) = -1;  // background
  const cv::Mat sent = MaskForTransport(ids);
  EXPECT_EQ(sent.type(), CV_32SC1);
  const sensor_msgs::msg::Image msg = EncodeImage(sent, ImageRole::kMask, 1, "camera");
  EXPECT_EQ(msg.encoding(), "32SC1");
  const auto m = DecodeImage(msg, ImageRole::kMask);
  ASSERT_EQ(m.error, "");
  EXPECT_EQ(m.image.at<int32_t>(0, 0), 65535);
  EXPECT_EQ(m.image.at<int32_t>(1, 1), 70000);
  EXPECT_EQ(m.image.at<int32_t>(2, 2), 70001);
  EXPECT_EQ(m.image.at<int32_t>(3, 3), 0);
  // Ids that fit go as 16 bits, as a segmenter's driver sends them.
  cv::Mat small(2, 2, CV_32SC1, cv::Scalar(7));
  small.at<int32_t>(0, 1) = -3;
  const cv::Mat sent_small = MaskForTransport(small);
  EXPECT_EQ(sent_small.type(), CV_16UC1);
  EXPECT_EQ(sent_small.at<uint16_t>(0, 1), 0);
  EXPECT_EQ(EncodeImage(sent_small, ImageRole::kMask, 1, "camera").encoding(), "16UC1");
}

TEST(ImageMessage, ConvertsRgbAndMillimetreDepth) {
  cv::Mat rgb(2, 2, CV_8UC3, cv::Scalar(10, 20, 30));
  auto msg = EncodeImage(rgb, ImageRole::kColour, 1, "camera");
  msg.encoding("rgb8");
  const auto c = DecodeImage(msg, ImageRole::kColour);
  EXPECT_EQ(c.image.at<cv::Vec3b>(0, 0), cv::Vec3b(30, 20, 10));

  cv::Mat mm(2, 2, CV_16UC1, cv::Scalar(1500));
  auto depth_msg = EncodeImage(mm, ImageRole::kMask, 1, "camera");  // 16UC1
  const auto d = DecodeImage(depth_msg, ImageRole::kDepth);
  ASSERT_EQ(d.error, "");
  EXPECT_FLOAT_EQ(d.image.at<float>(1, 1), 1.5f);
}

TEST(ImageMessage, NamesWhatIsWrongWithABadSample) {
  cv::Mat colour(4, 4, CV_8UC3, cv::Scalar(0));
  auto msg = EncodeImage(colour, ImageRole::kColour, 2'000'000'000LL, "camera");
  auto short_data = msg;
  short_data.data().resize(10);
  EXPECT_NE(DecodeImage(short_data, ImageRole::kColour).error.find("10 bytes of data for step 12 x height 4"),
            std::string::npos);
  auto unknown = msg;
  unknown.encoding("yuv422");
  EXPECT_NE(DecodeImage(unknown, ImageRole::kColour).error.find("encoding 'yuv422' is not supported"),
            std::string::npos);
  EXPECT_NE(DecodeImage(msg, ImageRole::kMask).error.find("encoding 'bgr8'"), std::string::npos);  // colour as mask
  auto narrow = msg;
  narrow.step(8);
  narrow.data().resize(32);
  EXPECT_NE(DecodeImage(narrow, ImageRole::kColour).error.find("step 8 is smaller"), std::string::npos);
  auto empty = msg;
  empty.width(0);
  EXPECT_NE(DecodeImage(empty, ImageRole::kColour).error.find("not usable"), std::string::npos);
  EXPECT_NE(DecodeImage(msg, ImageRole::kColour).error, "x");  // the good one decodes
  EXPECT_EQ(DecodeImage(msg, ImageRole::kColour).error, "");
}

TEST(ImageMessage, OdometryKeepsThePoseAndTakesTheIncrementNoiseFromTheTwistCovariance) {
  const SE3 T = SE3::Exp((Vec6() << 1, 2, 3, 0.1, 0.2, 0.3).finished());
  Vec6 twist_sigma;
  twist_sigma << 0.1, 0.2, 0.3, 0.01, 0.02, 0.03;
  std::string error;
  auto msg = EncodeOdometry(T, 5, "odom", "camera", twist_sigma);
  // A pose covariance (the drift accumulated over a drive) says nothing about one increment: not used.
  for (int i = 0; i < 6; ++i) msg.pose().covariance()[static_cast<size_t>(7 * i)] = 100.0;
  const auto pose = DecodeOdometry(msg, &error);
  ASSERT_TRUE(pose) << error;
  EXPECT_LT((pose->T_odom_camera.inverse() * T).Log().norm(), 1e-12);
  ASSERT_TRUE(pose->twist_sigma_per_s);
  EXPECT_TRUE(pose->twist_sigma_per_s->isApprox(twist_sigma, 1e-12));
  // No twist covariance (or only part of it): the configured increment sigma applies.
  EXPECT_FALSE(DecodeOdometry(EncodeOdometry(T, 5, "odom", "camera"), &error)->twist_sigma_per_s);
  auto partial = EncodeOdometry(T, 5, "odom", "camera", twist_sigma);
  partial.twist().covariance()[7] = 0.0;
  EXPECT_FALSE(DecodeOdometry(partial, &error)->twist_sigma_per_s);

  auto negative = EncodeOdometry(T, 5, "odom", "camera");
  negative.twist().covariance()[0] = -1.0;
  EXPECT_FALSE(DecodeOdometry(negative, &error));
  EXPECT_NE(error.find("twist covariance is not finite and non-negative"), std::string::npos);
  auto nan = EncodeOdometry(T, 5, "odom", "camera");
  nan.pose().pose().position().x(std::nan(""));
  EXPECT_FALSE(DecodeOdometry(nan, &error));
  EXPECT_NE(error.find("not finite"), std::string::npos);
  auto skewed = EncodeOdometry(T, 5, "odom", "camera");
  skewed.pose().pose().orientation().w(3.0);
  EXPECT_FALSE(DecodeOdometry(skewed, &error));
  EXPECT_NE(error.find("unit quaternion"), std::string::npos);
}

}  // namespace
}  // namespace dslam
