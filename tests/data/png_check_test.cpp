#include "data/png_check.h"

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "data/image_codec.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

TEST(PngCheck, AWholePngPassesACutOneIsNamedAndOtherFilesGoToTheDecoder) {
  const std::string dir = test::TempPath("png_check");
  fs::create_directories(dir);
  cv::Mat image(120, 200, CV_8UC3);
  cv::randu(image, 0, 255);
  const std::string whole = dir + "/whole.png";
  ASSERT_NO_THROW(dslam::WritePngFile(whole, image));
  const std::vector<unsigned char> bytes = ReadFileBytes(whole);
  EXPECT_EQ(FindPngProblem(bytes, 1'000'000), "");

  for (size_t keep : {bytes.size() - 1, bytes.size() / 2, size_t{20}, size_t{9}}) {
    const std::string problem =
        FindPngProblem(std::vector<unsigned char>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(keep)), 1'000'000);
    EXPECT_NE(problem.find("cut off"), std::string::npos) << keep << " bytes: " << problem;
  }
  // The header alone says how big the image is: refused before any pixel is decoded.
  const std::string problem = FindPngProblem(bytes, 200 * 119);
  EXPECT_NE(problem.find("200x120"), std::string::npos) << problem;
  EXPECT_NE(problem.find("max_image_pixels"), std::string::npos) << problem;

  // Not a PNG, or no bytes (a missing file): the decoder refuses it in its own words.
  EXPECT_EQ(FindPngProblem({'h', 'e', 'l', 'l', 'o'}, 1'000'000), "");
  EXPECT_EQ(FindPngProblem({}, 1'000'000), "");
  fs::remove_all(dir);
}

// The size is in the first 24 bytes (signature, IHDR's length, type, width, height): nothing is decoded.
TEST(PngCheck, TheSizeIsReadFromTheHeaderAlone) {
  cv::Mat image(120, 200, CV_16UC1, cv::Scalar(7));
  const std::vector<unsigned char> bytes = EncodePng(image);
  for (size_t keep : {bytes.size(), size_t{24}}) {
    const std::optional<PngSize> size =
        ReadPngSize(std::vector<unsigned char>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(keep)));
    ASSERT_TRUE(size) << keep;
    EXPECT_EQ(size->width, 200);
    EXPECT_EQ(size->height, 120);
  }
  EXPECT_FALSE(ReadPngSize(std::vector<unsigned char>(bytes.begin(), bytes.begin() + 23)));
  EXPECT_TRUE(HasPngSignature(std::vector<unsigned char>(bytes.begin(), bytes.begin() + 8)));
  EXPECT_FALSE(HasPngSignature(std::vector<unsigned char>(bytes.begin(), bytes.begin() + 7)));
  std::vector<unsigned char> not_ihdr = bytes;
  not_ihdr[12] = 'X';  // the first chunk's type
  EXPECT_FALSE(ReadPngSize(not_ihdr));
  EXPECT_FALSE(ReadPngSize({'h', 'e', 'l', 'l', 'o'}));
  EXPECT_FALSE(ReadPngSize(EncodeJpeg(cv::Mat(16, 16, CV_8UC3, cv::Scalar(1, 2, 3)))));
}


// A byte changed inside the image data (bit rot, a bad copy) fails that chunk's checksum: named, before libpng
// would print its own "libpng error" line.
TEST(PngCheck, ADamagedChunkFailsItsChecksum) {
  const std::string dir = test::TempPath("png_check_crc");
  fs::create_directories(dir);
  cv::Mat image(120, 200, CV_8UC3);
  cv::randu(image, 0, 255);
  ASSERT_NO_THROW(dslam::WritePngFile(dir + "/whole.png", image));
  const std::vector<unsigned char> bytes = ReadFileBytes(dir + "/whole.png");
  const std::string data(bytes.begin(), bytes.end());
  const size_t idat = data.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  for (size_t offset : {size_t{10}, size_t{500}, size_t{2000}}) {
    std::vector<unsigned char> damaged = bytes;
    damaged[idat + 4 + offset] ^= 0x01;
    const std::string problem = FindPngProblem(damaged, 1'000'000);
    EXPECT_NE(problem.find("chunk IDAT at byte " + std::to_string(idat - 4) + " fails its checksum"), std::string::npos)
        << offset << ": " << problem;
  }
  std::vector<unsigned char> damaged_header = bytes;
  damaged_header[24] ^= 0x01;  // IHDR's bit depth
  EXPECT_NE(FindPngProblem(damaged_header, 1'000'000).find("chunk IHDR at byte 8 fails its checksum"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dslam
