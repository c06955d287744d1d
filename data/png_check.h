#pragma once
// A PNG's structure checked before it is decoded: the signature, the header's size against a bound, every
// chunk whole up to IEND and each chunk's checksum (CRC-32). A truncated, damaged or oversized file is then
// refused with our own one-line message and without allocating its pixels (libpng would print its own line
// first, and a 20000x20000 image takes seconds and gigabytes to refuse). What a checksum cannot see (a file
// written damaged with valid checksums) is left to the decoder.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dslam {

// Empty when `bytes` (a whole file) are not a PNG (other formats go to the decoder as they are) or are a whole
// PNG of at most `max_pixels`; otherwise what is wrong, e.g. "PNG cut off in chunk IDAT at byte 20000 (...)" or
// "PNG chunk IDAT at byte 41 fails its checksum (damaged)".
std::string FindPngProblem(const std::vector<unsigned char>& bytes, int64_t max_pixels);

// The big-endian 32-bit number at `bytes` (PNG's lengths, sizes and checksums).
inline uint32_t PngBigEndian32(const unsigned char* bytes) {
  return (uint32_t{bytes[0]} << 24) | (uint32_t{bytes[1]} << 16) | (uint32_t{bytes[2]} << 8) | uint32_t{bytes[3]};
}

// Whether `bytes` start with the PNG signature.
bool HasPngSignature(const std::vector<unsigned char>& bytes);

// The image size a PNG's header gives, without decoding it; nullopt when `bytes` do not start with a PNG
// signature and a whole IHDR header.
struct PngSize {
  int64_t width = 0, height = 0;
};
std::optional<PngSize> ReadPngSize(const std::vector<unsigned char>& bytes);

}  // namespace dslam
