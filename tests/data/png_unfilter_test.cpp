#include "data/png_unfilter.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "support/png_by_hand.h"

namespace dslam {
namespace {

// Rows of every filter, for every pixel size PNG has, both paths: each gives the pixels back exactly. Noisy rows
// and smooth ones, so that Paeth picks each of its three neighbours.
TEST(PngUnfilter, EveryFilterOfEveryPixelSizeGivesThePixelsBack) {
  std::mt19937 random(3);
  for (const int bpp : {1, 2, 3, 4, 6, 8}) {
    const size_t row_bytes = 37 * static_cast<size_t>(bpp), rows = 30;
    std::vector<uint8_t> pixels(row_bytes * rows);
    for (size_t r = 0; r < rows; ++r)
      for (size_t i = 0; i < row_bytes; ++i)
        pixels[r * row_bytes + i] = static_cast<uint8_t>(r % 2 == 0 ? random() : 3 * r + i / static_cast<size_t>(bpp));
    const auto filter_of = [](size_t r) { return static_cast<int>(r % 5); };
    for (const bool simd : {true, false}) {
      std::vector<uint8_t> stored = test::FilterRows(pixels, row_bytes, static_cast<size_t>(bpp), filter_of);
      ASSERT_TRUE(UnfilterPngRows(stored.data(), row_bytes, rows, bpp, simd));
      for (size_t r = 0; r < rows; ++r)
        for (size_t i = 0; i < row_bytes; ++i)
          ASSERT_EQ(stored[r * (row_bytes + 1) + 1 + i], pixels[r * row_bytes + i])
              << "bpp " << bpp << " simd " << simd << " row " << r << " (filter " << filter_of(r) << ") byte " << i;
    }
  }
}

TEST(PngUnfilter, AFilterByteThatIsNotOneOfTheFiveIsRefused) {
  std::vector<uint8_t> stored = {0, 1, 2, 3, /* the second row */ 5, 1, 2, 3};
  EXPECT_FALSE(UnfilterPngRows(stored.data(), 3, 2, 3));
  stored[4] = 4;
  EXPECT_TRUE(UnfilterPngRows(stored.data(), 3, 2, 3));
}

}  // namespace
}  // namespace dslam
