#include "plugin/compressed_image.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dslam {
namespace {

cv::Mat TexturedColour() {
  cv::Mat colour(48, 64, CV_8UC3);
  for (int v = 0; v < colour.rows; ++v)
    for (int u = 0; u < colour.cols; ++u) colour.at<cv::Vec3b>(v, u) = cv::Vec3b(u * 4, v * 5, (u + v) * 2);
  return colour;
}

TEST(CompressedImage, PngColourDepthAndMaskRoundTrip) {
  const cv::Mat colour = TexturedColour();
  const auto msg = EncodeCompressedImage(colour, ImageRole::kColour, ImageCompression::kPng, 42, "camera");
  EXPECT_EQ(msg.format(), "bgr8; png compressed bgr8");
  const auto c = DecodeCompressedImage(msg, ImageRole::kColour);
  ASSERT_EQ(c.error, "");
  EXPECT_EQ(cv::norm(c.image, colour, cv::NORM_INF), 0.0);  // lossless
  EXPECT_EQ(StampToNs(msg.header().stamp()), 42);

  cv::Mat depth(48, 64, CV_32FC1, cv::Scalar(12.3456f));
  depth.at<float>(1, 1) = std::nanf("");
  depth.at<float>(2, 2) = 70.0f;  // beyond 16 bits of millimetres
  const auto d = DecodeCompressedImage(
      EncodeCompressedImage(depth, ImageRole::kDepth, ImageCompression::kJpeg, 1, "camera"), ImageRole::kDepth);
  ASSERT_EQ(d.error, "");
  EXPECT_EQ(d.image.type(), CV_32FC1);
  EXPECT_NEAR(d.image.at<float>(0, 0), 12.3456f, 0.0005f);  // millimetres
  EXPECT_EQ(d.image.at<float>(1, 1), 0.0f);                 // no depth stays no depth
  EXPECT_EQ(d.image.at<float>(2, 2), 0.0f);                 // out of range: no depth, not a wrong one

  cv::Mat ids(48, 64, CV_16UC1, cv::Scalar(0));
  ids(cv::Rect(10, 10, 20, 20)).setTo(4242);
  const auto m = DecodeCompressedImage(
      EncodeCompressedImage(ids, ImageRole::kMask, ImageCompression::kJpeg, 1, "camera"), ImageRole::kMask);
  ASSERT_EQ(m.error, "");
  EXPECT_EQ(cv::norm(m.image, ids, cv::NORM_INF), 0.0);  // masks are PNG whatever the colour's compression
}

TEST(CompressedImage, JpegColourIsCloseAndSmaller) {
  // A gradient with sensor noise, as a photograph: PNG keeps the noise exactly, JPEG need not.
  cv::Mat colour(120, 160, CV_8UC3);
  cv::Mat noise(120, 160, CV_8UC3);
  cv::randu(noise, 0, 6);
  for (int v = 0; v < colour.rows; ++v)
    for (int u = 0; u < colour.cols; ++u)
      colour.at<cv::Vec3b>(v, u) = cv::Vec3b(60 + u / 2, 80 + v / 2, 120) + noise.at<cv::Vec3b>(v, u);
  const auto jpeg = EncodeCompressedImage(colour, ImageRole::kColour, ImageCompression::kJpeg, 1, "camera");
  const auto png = EncodeCompressedImage(colour, ImageRole::kColour, ImageCompression::kPng, 1, "camera");
  EXPECT_EQ(jpeg.format(), "bgr8; jpeg compressed bgr8");
  EXPECT_LT(jpeg.data().size(), png.data().size());
  const auto c = DecodeCompressedImage(jpeg, ImageRole::kColour);
  ASSERT_EQ(c.error, "");
  EXPECT_LT(cv::norm(c.image, colour, cv::NORM_L1) / colour.total() / 3, 4.0);  // mean error under 4 grey levels
}

TEST(CompressedImage, CompressedDepthOfImageTransportIsReadPastItsHeader) {
  cv::Mat depth(48, 64, CV_32FC1, cv::Scalar(2.5f));
  auto msg = EncodeCompressedImage(depth, ImageRole::kDepth, ImageCompression::kPng, 1, "camera");
  std::vector<uint8_t> with_header(12, 0);  // compressed_depth_image_transport's configuration header
  with_header.insert(with_header.end(), msg.data().begin(), msg.data().end());
  msg.data() = with_header;
  msg.format("16UC1; compressedDepth png");
  const auto d = DecodeCompressedImage(msg, ImageRole::kDepth);
  ASSERT_EQ(d.error, "");
  EXPECT_FLOAT_EQ(d.image.at<float>(5, 5), 2.5f);
  msg.format("32FC1; compressedDepth png");
  EXPECT_NE(DecodeCompressedImage(msg, ImageRole::kDepth).error.find("not supported: send 16UC1"), std::string::npos);
}

TEST(CompressedImage, BadSamplesAreRefusedWithAMessageNamingThem) {
  const cv::Mat colour = TexturedColour();
  auto png = EncodeCompressedImage(colour, ImageRole::kColour, ImageCompression::kPng, 7, "camera");
  auto cut = png;
  cut.data().resize(cut.data().size() / 2);
  const std::string cut_error = DecodeCompressedImage(cut, ImageRole::kColour).error;
  EXPECT_NE(cut_error.find("compressed colour image at 7 ns"), std::string::npos) << cut_error;
  EXPECT_NE(cut_error.find("cut off"), std::string::npos) << cut_error;

  auto damaged = png;
  damaged.data()[60] ^= 0xFF;  // inside the first chunk's data: its checksum fails
  EXPECT_NE(DecodeCompressedImage(damaged, ImageRole::kColour).error.find("checksum"), std::string::npos);

  auto unknown = png;
  unknown.format("bgr8; webp compressed bgr8");
  EXPECT_NE(DecodeCompressedImage(unknown, ImageRole::kColour).error.find("neither png nor jpeg"), std::string::npos);

  auto jpeg = EncodeCompressedImage(colour, ImageRole::kColour, ImageCompression::kJpeg, 7, "camera");
  EXPECT_NE(DecodeCompressedImage(jpeg, ImageRole::kDepth).error.find("colour only"), std::string::npos);
  auto jpeg_cut = jpeg;
  jpeg_cut.data().resize(10);
  EXPECT_NE(DecodeCompressedImage(jpeg_cut, ImageRole::kColour).error, "");
  auto not_jpeg = jpeg;
  not_jpeg.data()[0] = 0;
  EXPECT_NE(DecodeCompressedImage(not_jpeg, ImageRole::kColour).error.find("not a JPEG"), std::string::npos);

  // A colour image sent as a mask decodes to three channels: refused by what it is.
  png.format("16UC1; png compressed 16UC1");
  EXPECT_NE(DecodeCompressedImage(png, ImageRole::kMask).error.find("3 channel(s) of 8 bits"), std::string::npos);
}

TEST(CompressedImage, MaskIdsAbove65535AreRefusedOnTheSendingSide) {
  cv::Mat ids(4, 6, CV_32SC1, cv::Scalar(0));
  ids.at<int32_t>(1, 1) = 70000;
  EXPECT_THROW(EncodeCompressedImage(ids, ImageRole::kMask, ImageCompression::kPng, 1, "camera"),
               std::invalid_argument);
  EXPECT_EQ(ParseImageCompression("jpeg"), ImageCompression::kJpeg);
  EXPECT_EQ(ParseImageCompression("gif"), std::nullopt);
}

}  // namespace
}  // namespace dslam
