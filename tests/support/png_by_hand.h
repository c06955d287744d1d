#pragma once
// PNG's parts written by hand for the decoder's tests, so that each can be chosen: the filter of every row, how
// the image data is split into chunks, which chunks come between them, a damaged or missing one.

#include <libdeflate.h>

#include <cstdint>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

namespace dslam::test {

inline int PaethPredictor(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

// `pixels` (rows of row_bytes, pixels of bpp bytes) filtered as an encoder does, row r with filter_of(r): a
// filter byte (0-4), then the row's predicted bytes.
inline std::vector<uint8_t> FilterRows(const std::vector<uint8_t>& pixels, size_t row_bytes, size_t bpp,
                                       const std::function<int(size_t)>& filter_of) {
  std::vector<uint8_t> out;
  const auto at = [&](size_t row, size_t col) { return int{pixels[row * row_bytes + col]}; };
  for (size_t r = 0; r < pixels.size() / row_bytes; ++r) {
    const int filter = filter_of(r);
    out.push_back(static_cast<uint8_t>(filter));
    for (size_t i = 0; i < row_bytes; ++i) {
      const int a = i >= bpp ? at(r, i - bpp) : 0, b = r > 0 ? at(r - 1, i) : 0,
                c = i >= bpp && r > 0 ? at(r - 1, i - bpp) : 0;
      const int predicted = filter == 1   ? a
                            : filter == 2 ? b
                            : filter == 3 ? (a + b) / 2
                            : filter == 4 ? PaethPredictor(a, b, c)
                                          : 0;
      out.push_back(static_cast<uint8_t>(at(r, i) - predicted));
    }
  }
  return out;
}

inline std::vector<uint8_t> ZlibCompress(const std::vector<uint8_t>& bytes) {
  libdeflate_compressor* deflater = libdeflate_alloc_compressor(6);
  std::vector<uint8_t> out(libdeflate_zlib_compress_bound(deflater, bytes.size()));
  out.resize(libdeflate_zlib_compress(deflater, bytes.data(), bytes.size(), out.data(), out.size()));
  libdeflate_free_compressor(deflater);
  return out;
}

struct PngChunk {
  std::string type;
  std::vector<uint8_t> data;
};

inline void PutBigEndian32(std::vector<uint8_t>* out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out->push_back(static_cast<uint8_t>(v >> shift));
}

// The signature, then each chunk with its length and checksum.
inline std::vector<uint8_t> AssemblePng(const std::vector<PngChunk>& chunks) {
  std::vector<uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  for (const PngChunk& chunk : chunks) {
    PutBigEndian32(&out, static_cast<uint32_t>(chunk.data.size()));
    const size_t type_at = out.size();
    out.insert(out.end(), chunk.type.begin(), chunk.type.end());
    out.insert(out.end(), chunk.data.begin(), chunk.data.end());
    PutBigEndian32(&out, libdeflate_crc32(0, out.data() + type_at, 4 + chunk.data.size()));
  }
  return out;
}

inline PngChunk PngHeader(int width, int height, int bit_depth, int colour_type, int interlace = 0) {
  PngChunk chunk{"IHDR", {}};
  PutBigEndian32(&chunk.data, static_cast<uint32_t>(width));
  PutBigEndian32(&chunk.data, static_cast<uint32_t>(height));
  chunk.data.insert(chunk.data.end(), {static_cast<uint8_t>(bit_depth), static_cast<uint8_t>(colour_type), 0, 0,
                                       static_cast<uint8_t>(interlace)});
  return chunk;
}

}  // namespace dslam::test
