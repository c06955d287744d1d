#include "data/png_check.h"

#include <array>
#include <fstream>

namespace dslam {
namespace {

uint32_t BigEndian32(const unsigned char* b) {
  return (uint32_t{b[0]} << 24) | (uint32_t{b[1]} << 16) | (uint32_t{b[2]} << 8) | uint32_t{b[3]};
}

}  // namespace

std::string FindPngProblem(const std::string& path, int64_t max_pixels) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return {};  // the decoder names a missing file
  const int64_t size = static_cast<int64_t>(in.tellg());
  in.seekg(0);
  static constexpr std::array<unsigned char, 8> kSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::array<unsigned char, 8> signature{};
  if (!in.read(reinterpret_cast<char*>(signature.data()), signature.size()) || signature != kSignature) return {};

  int64_t at = 8;
  bool first = true;
  for (;;) {
    unsigned char head[8];  // length, type
    if (at + 8 > size || !in.read(reinterpret_cast<char*>(head), 8))
      return "PNG cut off after byte " + std::to_string(at) + " of " + std::to_string(size) + " (no IEND chunk)";
    const uint32_t length = BigEndian32(head);
    const std::string type(reinterpret_cast<const char*>(head + 4), 4);
    if (first) {
      if (type != "IHDR" || length != 13) return "PNG does not start with its IHDR header";
      unsigned char ihdr[8];
      if (!in.read(reinterpret_cast<char*>(ihdr), 8)) return "PNG cut off in its IHDR header";
      const int64_t width = BigEndian32(ihdr), height = BigEndian32(ihdr + 4);
      if (width == 0 || height == 0) return "PNG of " + std::to_string(width) + "x" + std::to_string(height) + " pixels";
      if (width * height > max_pixels)
        return "PNG of " + std::to_string(width) + "x" + std::to_string(height) + " pixels, more than the " +
               std::to_string(max_pixels) + " allowed (dataset.max_image_pixels)";
      first = false;
    }
    const int64_t end = at + 8 + int64_t{length} + 4;  // data and CRC
    if (end > size)
      return "PNG cut off in chunk " + type + " at byte " + std::to_string(size) + " (the chunk ends at byte " +
             std::to_string(end) + ")";
    if (type == "IEND") return {};
    at = end;
    in.seekg(at);
  }
}

}  // namespace dslam
