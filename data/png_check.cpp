#include "data/png_check.h"

#include <libdeflate.h>

#include <algorithm>
#include <array>

namespace dslam {

bool HasPngSignature(const std::vector<unsigned char>& bytes) {
  static constexpr std::array<unsigned char, 8> kSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return bytes.size() >= kSignature.size() && std::equal(kSignature.begin(), kSignature.end(), bytes.begin());
}

std::optional<PngSize> ReadPngSize(const std::vector<unsigned char>& bytes) {
  // Signature, then the IHDR chunk's length (13) and type, then width and height.
  if (!HasPngSignature(bytes) || bytes.size() < 24) return std::nullopt;
  const unsigned char* head = bytes.data() + 8;
  if (PngBigEndian32(head) != 13 || std::string(reinterpret_cast<const char*>(head + 4), 4) != "IHDR")
    return std::nullopt;
  return PngSize{PngBigEndian32(head + 8), PngBigEndian32(head + 12)};
}

std::string FindPngProblem(const std::vector<unsigned char>& bytes, int64_t max_pixels) {
  if (!HasPngSignature(bytes)) return {};
  const int64_t size = static_cast<int64_t>(bytes.size());
  int64_t at = 8;
  bool first = true;
  for (;;) {
    if (at + 8 > size)
      return "PNG cut off after byte " + std::to_string(at) + " of " + std::to_string(size) + " (no IEND chunk)";
    const unsigned char* head = bytes.data() + at;  // length, type
    const uint32_t length = PngBigEndian32(head);
    const std::string type(reinterpret_cast<const char*>(head + 4), 4);
    if (first) {
      if (type != "IHDR" || length != 13) return "PNG does not start with its IHDR header";
      if (at + 16 > size) return "PNG cut off in its IHDR header";
      const int64_t width = PngBigEndian32(head + 8), height = PngBigEndian32(head + 12);
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
    // The CRC covers the chunk's type and data.
    const uint32_t crc = libdeflate_crc32(0, head + 4, 4 + size_t{length});
    if (crc != PngBigEndian32(bytes.data() + end - 4))
      return "PNG chunk " + type + " at byte " + std::to_string(at) + " fails its checksum (damaged)";
    if (type == "IEND") return {};
    at = end;
  }
}

}  // namespace dslam
