#include "data/image_codec.h"

#include <gtest/gtest.h>
#include <libdeflate.h>

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace dslam {
namespace {

cv::Mat Random(int type, uint64_t seed) {
  cv::Mat m(37, 53, type);  // odd sizes: rows are not a multiple of any SIMD width
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0, CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256);
  return m;
}

double MaxDifference(const cv::Mat& a, const cv::Mat& b) { return cv::norm(a, b, cv::NORM_INF); }

TEST(ImageCodec, PngRoundTripsEveryStoredLayoutExactly) {
  for (int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_16UC3, CV_8UC4, CV_16UC4}) {
    const cv::Mat image = Random(type, 7 + type);
    for (int level : {0, 1, 9})
      for (PngFilter filter : {PngFilter::kAdaptive, PngFilter::kNone}) {
        const std::vector<uint8_t> bytes = EncodePng(image, level, filter);
        std::string error;
        const cv::Mat back = DecodePng(bytes, ImageDecode::kUnchanged, &error);
        ASSERT_FALSE(back.empty()) << error;
        EXPECT_EQ(back.type(), type);
        EXPECT_EQ(MaxDifference(back, image), 0.0)
            << "type " << type << " level " << level << " filter " << static_cast<int>(filter);
      }
  }
}

// The stored rows, inflated: each a filter byte, then the row as the file holds it; empty if unreadable.
std::vector<uint8_t> StoredRows(const std::vector<uint8_t>& png, const cv::Mat& image) {
  std::vector<uint8_t> idat;
  for (size_t at = 8; at + 12 <= png.size();) {
    const size_t length = (size_t{png[at]} << 24) | (size_t{png[at + 1]} << 16) | (size_t{png[at + 2]} << 8) | png[at + 3];
    if (std::string(png.begin() + static_cast<std::ptrdiff_t>(at + 4), png.begin() + static_cast<std::ptrdiff_t>(at + 8)) == "IDAT")
      idat.insert(idat.end(), png.begin() + static_cast<std::ptrdiff_t>(at + 8),
                  png.begin() + static_cast<std::ptrdiff_t>(at + 8 + length));
    at += 12 + length;
  }
  const size_t row_bytes = 1 + image.cols * image.elemSize();
  std::vector<uint8_t> raw(row_bytes * static_cast<size_t>(image.rows));
  libdeflate_decompressor* inflater = libdeflate_alloc_decompressor();
  const libdeflate_result result =
      libdeflate_zlib_decompress(inflater, idat.data(), idat.size(), raw.data(), raw.size(), nullptr);
  libdeflate_free_decompressor(inflater);
  if (result != LIBDEFLATE_SUCCESS) return {};
  return raw;
}

// Each stored row's first byte: the PNG filter it was predicted with (0: none).
std::vector<int> RowFilters(const std::vector<uint8_t>& png, const cv::Mat& image) {
  const std::vector<uint8_t> raw = StoredRows(png, image);
  if (raw.empty()) return {};
  const size_t row_bytes = 1 + image.cols * image.elemSize();
  std::vector<int> filters;
  for (int v = 0; v < image.rows; ++v) filters.push_back(raw[row_bytes * static_cast<size_t>(v)]);
  return filters;
}

// PNG stores 16-bit samples most significant byte first, colour as RGB: checked on the stored bytes, so that
// the encoder and decoder cannot agree on a wrong order.
TEST(ImageCodec, SixteenBitSamplesAreStoredBigEndianAndDecodedInHostOrder) {
  cv::Mat grey(1, 2, CV_16UC1);
  grey.at<uint16_t>(0, 0) = 0x0102, grey.at<uint16_t>(0, 1) = 0xA0B0;
  cv::Mat bgr(1, 1, CV_16UC3);
  bgr.at<cv::Vec<uint16_t, 3>>(0, 0) = {0x0102, 0x0304, 0x0506};
  const std::vector<std::pair<cv::Mat, std::vector<uint8_t>>> cases = {
      {grey, {0, 0x01, 0x02, 0xA0, 0xB0}}, {bgr, {0, 0x05, 0x06, 0x03, 0x04, 0x01, 0x02}}};
  for (const auto& [image, stored] : cases) {
    const std::vector<uint8_t> png = EncodePng(image, 1, PngFilter::kNone);
    EXPECT_EQ(StoredRows(png, image), stored);
    const cv::Mat back = DecodePng(png, ImageDecode::kUnchanged);
    ASSERT_EQ(back.type(), image.type());
    EXPECT_EQ(MaxDifference(back, image), 0.0);
  }
}

// kNone stores every row unpredicted; kAdaptive predicts a smooth image's rows (so the option is what acts).
TEST(ImageCodec, PngFilterNoneStoresRowsUnpredicted) {
  cv::Mat gradient(40, 64, CV_8UC3);
  for (int v = 0; v < gradient.rows; ++v)
    for (int u = 0; u < gradient.cols; ++u) gradient.at<cv::Vec3b>(v, u) = cv::Vec3b(u * 3, v * 5, (u + v) * 2);
  const std::vector<int> none = RowFilters(EncodePng(gradient, 1, PngFilter::kNone), gradient);
  ASSERT_EQ(none.size(), 40u);
  EXPECT_EQ(std::count(none.begin(), none.end(), 0), 40);
  const std::vector<int> adaptive = RowFilters(EncodePng(gradient, 1, PngFilter::kAdaptive), gradient);
  ASSERT_EQ(adaptive.size(), 40u);
  EXPECT_GT(std::count_if(adaptive.begin(), adaptive.end(), [](int f) { return f != 0; }), 20);
}

TEST(ImageCodec, ColourDecodeGivesEightBitBgrFromAnyLayout) {
  const cv::Mat bgr = Random(CV_8UC3, 1);
  EXPECT_EQ(MaxDifference(DecodePng(EncodePng(bgr), ImageDecode::kColour), bgr), 0.0);  // channel order kept

  const cv::Mat grey = Random(CV_8UC1, 2);
  cv::Mat grey3;
  cv::cvtColor(grey, grey3, cv::COLOR_GRAY2BGR);
  EXPECT_EQ(MaxDifference(DecodePng(EncodePng(grey), ImageDecode::kColour), grey3), 0.0);  // replicated

  const cv::Mat deep = Random(CV_16UC3, 3);
  cv::Mat high_byte;
  deep.convertTo(high_byte, CV_8U, 1.0 / 256.0);  // rounds: the decoder truncates, so at most 1 apart
  EXPECT_LE(MaxDifference(DecodePng(EncodePng(deep), ImageDecode::kColour), high_byte), 1.0);

  const cv::Mat bgra = Random(CV_8UC4, 4);
  cv::Mat without_alpha;
  cv::cvtColor(bgra, without_alpha, cv::COLOR_BGRA2BGR);
  const cv::Mat back = DecodePng(EncodePng(bgra), ImageDecode::kColour);
  ASSERT_EQ(back.type(), CV_8UC3);
  EXPECT_EQ(MaxDifference(back, without_alpha), 0.0);
}

TEST(ImageCodec, JpegKeepsColourOrderAndGreyWithinItsLoss) {
  // Smooth images (JPEG's case), one channel much brighter than the others so a swapped order shows.
  cv::Mat bgr(64, 96, CV_8UC3);
  for (int v = 0; v < bgr.rows; ++v)
    for (int u = 0; u < bgr.cols; ++u) bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(200, static_cast<uchar>(u), 40);
  std::string error;
  const cv::Mat back = DecodeJpeg(EncodeJpeg(bgr, 95), ImageDecode::kUnchanged, &error);
  ASSERT_EQ(back.type(), CV_8UC3) << error;
  EXPECT_LE(MaxDifference(back, bgr), 8.0);

  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  const cv::Mat grey_back = DecodeJpeg(EncodeJpeg(grey, 95), ImageDecode::kUnchanged);
  ASSERT_EQ(grey_back.type(), CV_8UC1);
  EXPECT_LE(MaxDifference(grey_back, grey), 4.0);
  EXPECT_EQ(DecodeJpeg(EncodeJpeg(grey, 95), ImageDecode::kColour).type(), CV_8UC3);
}

TEST(ImageCodec, BrokenBytesGiveAnEmptyImageAndAReason) {
  const std::vector<uint8_t> png = EncodePng(Random(CV_8UC3, 5));
  const std::vector<uint8_t> jpeg = EncodeJpeg(Random(CV_8UC3, 6));
  const std::vector<std::pair<std::string, std::vector<uint8_t>>> cases = {
      {"empty", {}},
      {"text", {'h', 'e', 'l', 'l', 'o'}},
      {"png cut in half", std::vector<uint8_t>(png.begin(), png.begin() + static_cast<std::ptrdiff_t>(png.size() / 2))},
  };
  for (const auto& [what, bytes] : cases) {
    std::string error;
    EXPECT_TRUE(DecodePng(bytes, ImageDecode::kUnchanged, &error).empty()) << what;
    EXPECT_FALSE(error.empty()) << what;
  }
  std::string error;
  EXPECT_TRUE(DecodeJpeg({'h', 'e', 'l', 'l', 'o'}, ImageDecode::kUnchanged, &error).empty());
  EXPECT_FALSE(error.empty());
  EXPECT_TRUE(DecodePng(jpeg, ImageDecode::kUnchanged, &error).empty());  // a JPEG is not a PNG
  EXPECT_NE(error.find("not a PNG"), std::string::npos) << error;
}

// The decoder leaves zlib's Adler-32 unchecked because libpng checks each chunk's CRC: a byte changed inside
// the image data must still be refused by DecodePng itself (the datasets' FindPngProblem is not in its way).
TEST(ImageCodec, AByteChangedInTheImageDataIsRefused) {
  const std::vector<uint8_t> png = EncodePng(Random(CV_8UC3, 7));
  const size_t idat = std::string(png.begin(), png.end()).find("IDAT");  // the chunk's type; its data follows
  ASSERT_NE(idat, std::string::npos);
  ASSERT_LT(idat + 4 + 200, png.size());
  for (const size_t offset : {size_t{2}, size_t{40}, size_t{200}}) {  // zlib header, early and later data
    std::vector<uint8_t> damaged = png;
    damaged[idat + 4 + offset] ^= 0x10;
    std::string error;
    EXPECT_TRUE(DecodePng(damaged, ImageDecode::kUnchanged, &error).empty()) << "byte " << offset;
    EXPECT_NE(error.find("cannot be decoded"), std::string::npos) << error;
  }
}

TEST(ImageCodec, UnsupportedLayoutsAreRefusedByName) {
  EXPECT_THROW(EncodePng(cv::Mat(4, 4, CV_32FC1, cv::Scalar(1.0f))), std::invalid_argument);
  EXPECT_THROW(EncodePng(cv::Mat(4, 4, CV_8UC2, cv::Scalar(1))), std::invalid_argument);
  EXPECT_THROW(EncodePng(cv::Mat()), std::invalid_argument);
  EXPECT_THROW(EncodePng(Random(CV_8UC1, 1), 10), std::invalid_argument);
  EXPECT_THROW(EncodeJpeg(Random(CV_16UC1, 1)), std::invalid_argument);
  EXPECT_THROW(EncodeJpeg(Random(CV_8UC3, 1), 0), std::invalid_argument);
}

TEST(ImageCodec, FilesAreWrittenAndReadByNameWithClearErrors) {
  const std::string path = ::testing::TempDir() + "/image_codec_roundtrip.png";
  const cv::Mat image = Random(CV_16UC1, 9);
  WritePngFile(path, image);
  EXPECT_EQ(MaxDifference(ReadPngFile(path), image), 0.0);
  try {
    ReadPngFile(path + ".missing");
    ADD_FAILURE() << "a missing file was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ".missing"), std::string::npos) << e.what();
  }
  EXPECT_THROW(WritePngFile("/nonexistent_folder/x.png", image), std::runtime_error);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace dslam
