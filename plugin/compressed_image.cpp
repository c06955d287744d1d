#include "plugin/compressed_image.h"

#include <cctype>
#include <stdexcept>

#include "data/image_codec.h"
#include "data/png_check.h"

namespace dslam {

namespace {

constexpr int64_t kMaxCompressedPixels = 16384LL * 16384LL;  // as a raw Image's width and height bound
constexpr double kDepthMmPerMetre = 1000.0;

// The size a JPEG's frame header (SOFn) gives, without decoding; an error when the markers up to it are not
// a JPEG's. (libjpeg would print its own warnings for damaged data and allocate whatever the header says.)
std::string FindJpegProblem(const std::vector<uint8_t>& b, int64_t max_pixels) {
  if (b.size() < 4 || b[0] != 0xFF || b[1] != 0xD8) return "not a JPEG (no start-of-image marker)";
  size_t i = 2;
  while (i + 4 <= b.size()) {
    if (b[i] != 0xFF) return "JPEG marker expected at byte " + std::to_string(i);
    const uint8_t marker = b[i + 1];
    if (marker == 0xFF) {  // fill byte
      ++i;
      continue;
    }
    if ((marker >= 0xD0 && marker <= 0xD7) || marker == 0x01) {  // markers without a length
      i += 2;
      continue;
    }
    const size_t length = (static_cast<size_t>(b[i + 2]) << 8) | b[i + 3];
    if (length < 2 || i + 2 + length > b.size()) return "JPEG cut off in the segment at byte " + std::to_string(i);
    const bool frame_header = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame_header) {
      if (length < 8) return "JPEG frame header too short at byte " + std::to_string(i);
      const int64_t height = (static_cast<int64_t>(b[i + 5]) << 8) | b[i + 6];
      const int64_t width = (static_cast<int64_t>(b[i + 7]) << 8) | b[i + 8];
      if (width == 0 || height == 0 || width * height > max_pixels)
        return "JPEG of " + std::to_string(width) + "x" + std::to_string(height) + " pixels is not usable";
      return {};
    }
    if (marker == 0xDA || marker == 0xD9) break;  // scan data or the end before any frame header
    i += 2 + length;
  }
  return "JPEG without a frame header";
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

std::optional<ImageCompression> ParseImageCompression(const std::string& name) {
  if (name == "none") return ImageCompression::kNone;
  if (name == "png") return ImageCompression::kPng;
  if (name == "jpeg") return ImageCompression::kJpeg;
  return std::nullopt;
}

sensor_msgs::msg::CompressedImage EncodeCompressedImage(const cv::Mat& image, ImageRole role,
                                                        ImageCompression compression, int64_t t_ns,
                                                        const std::string& frame_id) {
  if (compression == ImageCompression::kNone)
    throw std::invalid_argument("EncodeCompressedImage: no compression asked for");
  sensor_msgs::msg::CompressedImage msg;
  msg.header().stamp(NsToStamp(t_ns));
  msg.header().frame_id(frame_id);
  cv::Mat pixels;
  std::string encoding;
  bool jpeg = false;
  switch (role) {
    case ImageRole::kColour:
      pixels = image;
      encoding = image.channels() == 3 ? "bgr8" : "mono8";
      jpeg = compression == ImageCompression::kJpeg;
      break;
    case ImageRole::kDepth: {
      // Millimetres in 16 bits: depth beyond 65.535 m (or none, NaN, negative) becomes 0, "no depth".
      cv::Mat mm = image * kDepthMmPerMetre;
      cv::patchNaNs(mm, 0.0);
      mm.setTo(0.0, (mm > 65535.0) | (mm < 0.0));
      mm.convertTo(pixels, CV_16UC1);
      encoding = "16UC1";
      break;
    }
    case ImageRole::kMask: {
      const cv::Mat ids = MaskForTransport(image);
      if (ids.depth() != CV_16U)
        throw std::invalid_argument(
            "instance ids above 65535 cannot travel as a 16-bit PNG: publish masks uncompressed");
      pixels = ids;
      encoding = "16UC1";
      break;
    }
  }
  std::vector<uint8_t> bytes;
  try {
    bytes = jpeg ? EncodeJpeg(pixels, 90) : EncodePng(pixels, 1);  // PNG level 1: fast, and most of the gain
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("cannot compress the ") + ImageRoleName(role) + ": " + e.what());
  }
  msg.format(encoding + "; " + (jpeg ? "jpeg" : "png") + " compressed " + encoding);
  msg.data() = std::move(bytes);
  return msg;
}

DecodedImage DecodeCompressedImage(const sensor_msgs::msg::CompressedImage& msg, ImageRole role) {
  DecodedImage out;
  const std::string what = std::string("compressed ") + ImageRoleName(role) + " at " +
                           std::to_string(StampToNs(msg.header().stamp())) + " ns";
  const std::string format = Lower(msg.format());
  const bool compressed_depth = format.find("compresseddepth") != std::string::npos;
  const bool png = format.find("png") != std::string::npos;
  const bool jpeg = format.find("jpeg") != std::string::npos || format.find("jpg") != std::string::npos;
  if (png == jpeg) {
    out.error = what + ": format '" + msg.format() + "' is neither png nor jpeg";
    return out;
  }
  if (jpeg && role != ImageRole::kColour) {
    out.error =
        what + ": format '" + msg.format() + "': JPEG is lossy, accepted for colour only (send depth and masks as png)";
    return out;
  }
  if (compressed_depth && format.rfind("32fc1", 0) == 0) {
    out.error =
        what + ": format '" + msg.format() + "' (inverse depth quantised to 16 bits) is not supported: send 16UC1";
    return out;
  }
  if (compressed_depth && role != ImageRole::kDepth) {
    out.error = what + ": format '" + msg.format() + "' is for depth images";
    return out;
  }
  // compressed_depth_image_transport puts a 12-byte header (format, two quantisation parameters) first.
  const size_t offset = compressed_depth ? 12 : 0;
  if (msg.data().size() <= offset) {
    out.error = what + ": no data";
    return out;
  }
  // The sample's own bytes, copied only when a header must be skipped (the checks take a whole vector).
  std::vector<uint8_t> after_header;
  if (offset > 0) after_header.assign(msg.data().begin() + static_cast<std::ptrdiff_t>(offset), msg.data().end());
  const std::vector<uint8_t>& bytes = offset > 0 ? after_header : msg.data();
  const std::string problem =
      png ? FindPngProblem(bytes, kMaxCompressedPixels) : FindJpegProblem(bytes, kMaxCompressedPixels);
  if (!problem.empty() || (png && (bytes.size() < 8 || bytes[1] != 'P' || bytes[2] != 'N' || bytes[3] != 'G'))) {
    out.error = what + ": " + (problem.empty() ? "not a PNG" : problem);
    return out;
  }
  std::string decode_error;
  const cv::Mat decoded = png ? DecodePng(bytes, ImageDecode::kUnchanged, &decode_error)
                              : DecodeJpeg(bytes, ImageDecode::kUnchanged, &decode_error);
  if (decoded.empty()) {
    out.error = what + ": cannot be decoded (" + decode_error + ")";
    return out;
  }
  const std::string pixels =
      std::to_string(decoded.channels()) + " channel(s) of " + std::to_string(decoded.elemSize1() * 8) + " bits";
  switch (role) {
    case ImageRole::kColour:
      if (decoded.depth() != CV_8U || (decoded.channels() != 3 && decoded.channels() != 1)) break;
      out.image = decoded;
      return out;
    case ImageRole::kDepth:
      if (decoded.type() != CV_16UC1) break;
      decoded.convertTo(out.image, CV_32FC1, 1.0 / kDepthMmPerMetre);
      return out;
    case ImageRole::kMask:
      if (decoded.type() == CV_8UC1) decoded.convertTo(decoded, CV_16UC1);
      if (decoded.type() != CV_16UC1) break;
      out.image = decoded;
      return out;
  }
  out.error = what + ": decodes to " + pixels + ", not what a " + ImageRoleName(role) + " takes";
  return out;
}

}  // namespace dslam
