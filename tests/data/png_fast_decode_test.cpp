#include "data/png_fast_decode.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "data/image_codec.h"
#include "support/png_by_hand.h"

namespace dslam {
namespace {

using test::AssemblePng;
using test::PngChunk;
using test::PngHeader;

// The stored rows filtered row r with filter_of(r), then compressed: an IDAT chunk's data.
std::vector<uint8_t> ImageData(const std::vector<uint8_t>& rows, size_t row_bytes, size_t bpp,
                               int (*filter_of)(size_t)) {
  return test::ZlibCompress(test::FilterRows(rows, row_bytes, bpp, filter_of));
}

// Half the rows noise, half gradients: Paeth then picks each of its neighbours.
std::vector<uint8_t> PixelRows(int width, int height, size_t bpp, unsigned seed) {
  std::srand(seed);
  std::vector<uint8_t> rows(static_cast<size_t>(width * height) * bpp);
  for (size_t i = 0; i < rows.size(); ++i) {
    const size_t row = i / (static_cast<size_t>(width) * bpp);
    rows[i] = static_cast<uint8_t>(row % 3 == 0 ? std::rand() : row * 5 + i / bpp);
  }
  return rows;
}

int EachFilterInTurn(size_t r) { return static_cast<int>(r % 5); }
int OnlyNone(size_t) { return 0; }

struct Layout {
  int bit_depth, colour_type, channels;
};

// A PNG of `layout` with its image data split into IDAT chunks of at most `split` bytes.
std::vector<uint8_t> MakePng(const Layout& layout, int width, int height, size_t split, unsigned seed) {
  const size_t bpp = static_cast<size_t>(layout.channels * layout.bit_depth / 8);
  const std::vector<uint8_t> data =
      ImageData(PixelRows(width, height, bpp, seed), static_cast<size_t>(width) * bpp, bpp, EachFilterInTurn);
  std::vector<PngChunk> chunks = {PngHeader(width, height, layout.bit_depth, layout.colour_type), {"tEXt", {'a', 0, 'b'}}};
  for (size_t at = 0; at < data.size(); at += split)
    chunks.push_back({"IDAT", std::vector<uint8_t>(data.begin() + static_cast<std::ptrdiff_t>(at),
                                                   data.begin() + static_cast<std::ptrdiff_t>(std::min(data.size(), at + split)))});
  chunks.push_back({"IEND", {}});
  return AssemblePng(chunks);
}

void ExpectSameImage(const cv::Mat& a, const cv::Mat& b, const std::string& what) {
  ASSERT_EQ(a.type(), b.type()) << what;
  ASSERT_EQ(a.size(), b.size()) << what;
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0) << what;
}

// The layouts this path takes, every filter, one IDAT or many, both decode modes: the path takes them, and its
// pixels are libpng's.
TEST(PngFastDecode, TakesTheCommonLayoutsAndDecodesThemAsLibpngDoes) {
  const std::vector<Layout> layouts = {{8, 0, 1}, {8, 2, 3}, {8, 6, 4}, {16, 0, 1}};
  unsigned seed = 1;
  for (const Layout& layout : layouts)
    for (const size_t split : {size_t{1} << 30, size_t{97}})
      for (const ImageDecode mode : {ImageDecode::kUnchanged, ImageDecode::kColour}) {
        const std::string what = "bit depth " + std::to_string(layout.bit_depth) + ", colour type " +
                                 std::to_string(layout.colour_type) + ", IDAT split " + std::to_string(split) +
                                 (mode == ImageDecode::kColour ? ", colour" : ", unchanged");
        const std::vector<uint8_t> png = MakePng(layout, 53, 41, split, seed++);
        std::string error;
        const cv::Mat by_libpng = DecodePngByLibpng(png, mode, &error);
        ASSERT_FALSE(by_libpng.empty()) << what << ": " << error;
        cv::Mat fast;
        const bool taken = DecodeCommonPng(png, mode, &fast);
        if (layout.bit_depth == 16 && mode == ImageDecode::kColour) {  // to 8-bit colour: libpng's transforms
          EXPECT_FALSE(taken) << what;
          EXPECT_TRUE(fast.empty()) << what;
          continue;
        }
        ASSERT_TRUE(taken) << what;
        ExpectSameImage(fast, by_libpng, what);
        ExpectSameImage(DecodePng(png, mode), by_libpng, what);
      }
}

// Frames of different sizes one after another on one thread (the path keeps its buffers between images).
TEST(PngFastDecode, ImagesOfChangingSizesDecodeAlike) {
  const Layout rgb{8, 2, 3};
  for (const auto& [width, height] : std::vector<std::pair<int, int>>{{300, 200}, {7, 3}, {300, 200}, {1, 1}, {64, 500}}) {
    const std::vector<uint8_t> png = MakePng(rgb, width, height, 8192, static_cast<unsigned>(width + height));
    cv::Mat fast;
    ASSERT_TRUE(DecodeCommonPng(png, ImageDecode::kUnchanged, &fast)) << width << "x" << height;
    ExpectSameImage(fast, DecodePngByLibpng(png, ImageDecode::kUnchanged), std::to_string(width) + "x" + std::to_string(height));
  }
}

// What the path leaves to libpng, and DecodePng then gives libpng's answer: the same image, or the same error.
TEST(PngFastDecode, LeavesOtherLayoutsAndAnythingUnusualToLibpng) {
  const Layout rgb{8, 2, 3};
  const std::vector<uint8_t> sound = MakePng(rgb, 20, 10, 1 << 30, 5);
  // The sound file's chunks: signature (8), IHDR (25), tEXt (15), IDAT, IEND (12).
  const size_t idat_at = 8 + 25 + 15;
  const std::vector<uint8_t> idat_data(sound.begin() + static_cast<std::ptrdiff_t>(idat_at + 8), sound.end() - 12 - 4);
  const PngChunk header = PngHeader(20, 10, 8, 2), end{"IEND", {}}, idat{"IDAT", idat_data};
  const size_t half = idat_data.size() / 2;
  const PngChunk first_half{"IDAT", std::vector<uint8_t>(idat_data.begin(), idat_data.begin() + static_cast<std::ptrdiff_t>(half))};
  const PngChunk second_half{"IDAT", std::vector<uint8_t>(idat_data.begin() + static_cast<std::ptrdiff_t>(half), idat_data.end())};
  const std::vector<uint8_t> rows_16bit_rgb = PixelRows(20, 10, 6, 9);
  std::vector<uint8_t> bad_filter(10 * 61, 0);  // ten rows of a filter byte and 60 bytes
  bad_filter[61 * 4] = 7;

  std::vector<std::pair<std::string, std::vector<uint8_t>>> cases = {
      {"16-bit RGB", AssemblePng({PngHeader(20, 10, 16, 2), {"IDAT", ImageData(rows_16bit_rgb, 120, 6, OnlyNone)}, end})},
      {"grey and alpha", AssemblePng({PngHeader(20, 10, 8, 4), {"IDAT", ImageData(PixelRows(20, 10, 2, 3), 40, 2, OnlyNone)}, end})},
      {"interlaced", AssemblePng({PngHeader(20, 10, 8, 2, 1), idat, end})},
      {"a palette", AssemblePng({header, {"PLTE", {1, 2, 3}}, idat, end})},
      {"an unknown critical chunk", AssemblePng({header, {"ABCD", {1}}, idat, end})},
      {"a chunk between the IDATs", AssemblePng({header, first_half, {"tEXt", {'a', 0, 'b'}}, second_half, end})},
      {"no IEND", AssemblePng({header, idat})},
      {"too little image data", AssemblePng({header, first_half, end})},
      {"image data of another size", AssemblePng({PngHeader(20, 9, 8, 2), idat, end})},
      {"a filter byte of 7", AssemblePng({header, {"IDAT", test::ZlibCompress(bad_filter)}, end})},
  };
  std::vector<uint8_t> damaged = sound;
  damaged[idat_at + 8 + 5] ^= 0x01;
  cases.push_back({"a damaged IDAT", damaged});
  std::vector<uint8_t> damaged_text = sound;
  damaged_text[8 + 25 + 8] ^= 0x01;  // the tEXt chunk's first data byte: libpng warns and decodes
  cases.push_back({"a damaged ancillary chunk", damaged_text});

  for (const auto& [what, png] : cases) {
    cv::Mat fast;
    EXPECT_FALSE(DecodeCommonPng(png, ImageDecode::kUnchanged, &fast)) << what;
    EXPECT_TRUE(fast.empty()) << what;
    std::string error, libpng_error;
    const cv::Mat decoded = DecodePng(png, ImageDecode::kUnchanged, &error);
    const cv::Mat by_libpng = DecodePngByLibpng(png, ImageDecode::kUnchanged, &libpng_error);
    EXPECT_EQ(error, libpng_error) << what;
    EXPECT_EQ(decoded.empty(), by_libpng.empty()) << what;
    if (!decoded.empty()) ExpectSameImage(decoded, by_libpng, what);
  }
  // A header far larger than its data could fill (deflate expands a byte to at most 1032): refused before the
  // rows are allocated (30 GB here; libpng would try, so only the path is asked).
  cv::Mat outsized;
  EXPECT_FALSE(DecodeCommonPng(AssemblePng({PngHeader(100000, 100000, 8, 2), idat, end}), ImageDecode::kUnchanged, &outsized));
  // The sound file itself is taken: the cases above fail for what they change.
  cv::Mat fast;
  EXPECT_TRUE(DecodeCommonPng(sound, ImageDecode::kUnchanged, &fast));
  EXPECT_TRUE(DecodeCommonPng(AssemblePng({header, first_half, second_half, end}), ImageDecode::kUnchanged, &fast));
}

// Damage of every kind, the checksums made good again so that it reaches the decoders: whatever the path takes,
// libpng decodes to the same pixels, and nothing the path leaves changes DecodePng's answer from libpng's.
TEST(PngFastDecode, DamagedFilesWithGoodChecksumsDecodeAsLibpngDecodesThem) {
  std::mt19937 random(11);
  const std::vector<Layout> layouts = {{8, 0, 1}, {8, 2, 3}, {8, 6, 4}, {16, 0, 1}};
  int taken = 0, left = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const Layout& layout = layouts[static_cast<size_t>(trial) % layouts.size()];
    std::vector<uint8_t> png = MakePng(layout, 9 + trial % 23, 5 + trial % 17, 40 + trial % 200, static_cast<unsigned>(trial));
    // Change 1-3 bytes after the signature (any chunk: lengths, types, header fields, image data).
    const int changes = 1 + static_cast<int>(random() % 3);
    for (int c = 0; c < changes; ++c) png[8 + random() % (png.size() - 8)] ^= static_cast<uint8_t>(1 + random() % 255);
    // Make each chunk's checksum good again, where its length still fits.
    for (size_t at = 8; at + 12 <= png.size();) {
      const size_t length = (size_t{png[at]} << 24) | (size_t{png[at + 1]} << 16) | (size_t{png[at + 2]} << 8) | png[at + 3];
      if (length > png.size() - at - 12) break;
      const uint32_t crc = libdeflate_crc32(0, png.data() + at + 4, 4 + length);
      for (int k = 0; k < 4; ++k) png[at + 8 + length + static_cast<size_t>(k)] = static_cast<uint8_t>(crc >> (24 - 8 * k));
      at += 12 + length;
    }
    const ImageDecode mode = trial % 2 == 0 ? ImageDecode::kUnchanged : ImageDecode::kColour;
    std::string error, libpng_error;
    const cv::Mat by_libpng = DecodePngByLibpng(png, mode, &libpng_error);
    cv::Mat fast;
    if (DecodeCommonPng(png, mode, &fast)) {
      ++taken;
      ASSERT_FALSE(by_libpng.empty()) << "trial " << trial << ": the path decoded what libpng refuses: " << libpng_error;
      ExpectSameImage(fast, by_libpng, "trial " + std::to_string(trial));
    } else {
      ++left;
      const cv::Mat decoded = DecodePng(png, mode, &error);
      EXPECT_EQ(error, libpng_error) << "trial " << trial;
      EXPECT_EQ(decoded.empty(), by_libpng.empty()) << "trial " << trial;
    }
  }
  // Both sides were exercised: some changes leave a file the path still takes (in the text chunk, or in a checksum
  // that is made good again).
  EXPECT_GT(taken, 10);
  EXPECT_GT(left, 100);
}

}  // namespace
}  // namespace dslam
