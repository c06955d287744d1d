#include "data/png_fast_decode.h"

#include <libdeflate.h>

#include <cstring>
#include <memory>

#include <opencv2/imgproc.hpp>

#include "data/png_check.h"
#include "data/png_unfilter.h"

namespace dslam {
namespace {

bool IsChunkType(const uint8_t* type, const char* name) { return std::memcmp(type, name, 4) == 0; }

bool IsLetter(uint8_t c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }

// Deflate's largest expansion of a compressed byte, and the most inflated rows a thread keeps between images
// (a 4096x4096 RGBA frame).
constexpr size_t kDeflateMaxExpansion = 1032;
constexpr size_t kRowsKeptBytes = size_t{4096} * (1 + 4096 * 4);

// libpng refuses a width or height above this unless told otherwise (PNG_USER_WIDTH_MAX, PNG_USER_HEIGHT_MAX).
constexpr uint32_t kLibpngSideLimit = 1'000'000;

struct FreeInflater {
  void operator()(libdeflate_decompressor* inflater) const { libdeflate_free_decompressor(inflater); }
};

// Kept per thread between images: the joined IDAT data, the inflated rows and the inflater, so that a stream of
// same-sized frames allocates (and page-faults) nothing after its first; the largest image's rows stay allocated.
struct DecodeScratch {
  std::vector<uint8_t> compressed;
  std::vector<uint8_t> rows;
  std::unique_ptr<libdeflate_decompressor, FreeInflater> inflater;
};

struct PngLayout {
  uint32_t width = 0, height = 0;
  int bit_depth = 0, colour_type = 0, channels = 0;
};

// The layouts this path takes: 8-bit grey (0), RGB (2) and RGBA (6); 16-bit grey unless asked for colour.
bool ReadPngLayout(const uint8_t* data, ImageDecode mode, PngLayout* layout) {
  layout->width = PngBigEndian32(data);
  layout->height = PngBigEndian32(data + 4);
  layout->bit_depth = data[8];
  layout->colour_type = data[9];
  const bool compression_ok = data[10] == 0, filter_ok = data[11] == 0, not_interlaced = data[12] == 0;
  if (!compression_ok || !filter_ok || !not_interlaced) return false;
  if (layout->width == 0 || layout->height == 0 || layout->width > kLibpngSideLimit ||
      layout->height > kLibpngSideLimit)
    return false;
  if (layout->bit_depth == 8) {
    layout->channels = layout->colour_type == 0 ? 1 : layout->colour_type == 2 ? 3 : layout->colour_type == 6 ? 4 : 0;
  } else if (layout->bit_depth == 16 && layout->colour_type == 0 && mode == ImageDecode::kUnchanged) {
    layout->channels = 1;
  }
  return layout->channels > 0;
}

// The inflated rows (a filter byte before each), undone, to OpenCV's layout: BGR(A), 16-bit in host order.
void RowsToImage(const PngLayout& layout, ImageDecode mode, uint8_t* rows, cv::Mat* image) {
  const int height = static_cast<int>(layout.height), width = static_cast<int>(layout.width);
  const size_t stride = 1 + size_t{layout.width} * static_cast<size_t>(layout.channels * layout.bit_depth / 8);
  if (layout.bit_depth == 16) {
    image->create(height, width, CV_16UC1);
    for (int v = 0; v < height; ++v) {
      const uint8_t* in = rows + static_cast<size_t>(v) * stride + 1;
      uint16_t* out = image->ptr<uint16_t>(v);
      for (int u = 0; u < width; ++u) out[u] = static_cast<uint16_t>((in[2 * u] << 8) | in[2 * u + 1]);
    }
    return;
  }
  const cv::Mat stored(height, width, CV_8UC(layout.channels), rows + 1, stride);
  const bool colour = mode == ImageDecode::kColour;
  switch (layout.channels) {
    case 1:
      if (colour) cv::cvtColor(stored, *image, cv::COLOR_GRAY2BGR);
      else stored.copyTo(*image);
      break;
    case 3:
      cv::cvtColor(stored, *image, cv::COLOR_RGB2BGR);
      break;
    default:
      cv::cvtColor(stored, *image, colour ? cv::COLOR_RGBA2BGR : cv::COLOR_RGBA2BGRA);
      break;
  }
}

}  // namespace

bool DecodeCommonPng(const std::vector<uint8_t>& bytes, ImageDecode mode, cv::Mat* image) {
  if (!HasPngSignature(bytes)) return false;
  thread_local DecodeScratch scratch;
  const uint8_t* data = bytes.data();
  const size_t size = bytes.size();
  PngLayout layout;
  const uint8_t* compressed = nullptr;  // the one IDAT chunk's data, or scratch.compressed when there are several
  size_t compressed_size = 0;
  int idat_chunks = 0;
  bool idat_ended = false;
  scratch.compressed.clear();
  for (size_t at = 8;;) {
    if (size - at < 12) return false;  // cut off before IEND
    const uint32_t length = PngBigEndian32(data + at);
    if (length > size - at - 12) return false;
    const uint8_t* type = data + at + 4;
    const uint8_t* body = type + 4;
    if (!IsLetter(type[0]) || !IsLetter(type[1]) || !IsLetter(type[2]) || !IsLetter(type[3])) return false;
    if (libdeflate_crc32(0, type, 4 + size_t{length}) != PngBigEndian32(body + length)) return false;
    if (at == 8) {
      if (!IsChunkType(type, "IHDR") || length != 13 || !ReadPngLayout(body, mode, &layout)) return false;
    } else if (IsChunkType(type, "IDAT")) {
      if (idat_ended) return false;
      if (++idat_chunks == 2) scratch.compressed.assign(compressed, compressed + compressed_size);
      if (idat_chunks == 1) compressed = body;
      else scratch.compressed.insert(scratch.compressed.end(), body, body + length);
      compressed_size += length;
    } else if (IsChunkType(type, "IEND")) {
      break;
    } else {
      idat_ended = idat_chunks > 0;
      const bool critical = (type[0] & 0x20) == 0;  // an upper-case first letter
      if (critical) return false;
    }
    at += 12 + size_t{length};
  }
  if (idat_chunks == 0) return false;
  if (idat_chunks > 1) compressed = scratch.compressed.data();

  const size_t row_bytes = size_t{layout.width} * static_cast<size_t>(layout.channels * layout.bit_depth / 8);
  const size_t rows_size = (1 + row_bytes) * layout.height;
  // Deflate expands a byte to at most 1032 bytes (a 258-byte match in as little as two bits): a header that claims
  // more rows than its data could hold is damaged, and nothing that size is allocated for it.
  if (rows_size / kDeflateMaxExpansion > compressed_size + 1) return false;
  if (!scratch.inflater) scratch.inflater.reset(libdeflate_alloc_decompressor());
  if (!scratch.inflater) return false;
  // A stream's frames keep their rows between images; one outsized image does not keep its own.
  std::vector<uint8_t> outsized;
  std::vector<uint8_t>& rows = rows_size > kRowsKeptBytes ? outsized : scratch.rows;
  if (rows.size() < rows_size) rows.resize(rows_size);
  size_t read = 0, written = 0;
  if (libdeflate_zlib_decompress_ex(scratch.inflater.get(), compressed, compressed_size, rows.data(), rows_size,
                                    &read, &written) != LIBDEFLATE_SUCCESS ||
      read != compressed_size || written != rows_size)
    return false;
  if (!UnfilterPngRows(rows.data(), row_bytes, layout.height, layout.channels * layout.bit_depth / 8)) return false;
  RowsToImage(layout, mode, rows.data(), image);
  return true;
}

}  // namespace dslam
