#include "data/image_codec.h"

#include <spng.h>
#include <turbojpeg.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace dslam {
namespace {

struct SpngDeleter {
  void operator()(spng_ctx* ctx) const { spng_ctx_free(ctx); }
};
using Spng = std::unique_ptr<spng_ctx, SpngDeleter>;

struct TurboDeleter {
  void operator()(void* handle) const { tjDestroy(handle); }
};
using Turbo = std::unique_ptr<void, TurboDeleter>;

cv::Mat Fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return {};
}

// RGB(A) as stored to OpenCV's BGR(A), in place.
void ToBgr(cv::Mat& image) {
  if (image.channels() == 3) cv::cvtColor(image, image, cv::COLOR_RGB2BGR);
  if (image.channels() == 4) cv::cvtColor(image, image, cv::COLOR_RGBA2BGRA);
}

}  // namespace

cv::Mat DecodePng(const std::vector<uint8_t>& bytes, ImageDecode mode, std::string* error) {
  Spng ctx(spng_ctx_new(0));
  if (!ctx) return Fail(error, "out of memory");
  // Chunks other than the image (text, ICC profiles) are bounded: the file is untrusted.
  spng_set_chunk_limits(ctx.get(), 64u << 20, 64u << 20);
  if (int e = spng_set_png_buffer(ctx.get(), bytes.data(), bytes.size())) return Fail(error, spng_strerror(e));
  spng_ihdr ihdr{};
  if (int e = spng_get_ihdr(ctx.get(), &ihdr)) return Fail(error, std::string("not a PNG (") + spng_strerror(e) + ")");
  const int rows = static_cast<int>(ihdr.height), cols = static_cast<int>(ihdr.width);
  const bool sixteen = ihdr.bit_depth == 16;
  int format = 0, type = 0, flags = 0;
  if (mode == ImageDecode::kColour) {
    format = SPNG_FMT_RGB8, type = CV_8UC3;
  } else {
    spng_trns trns{};
    const bool has_trns = spng_get_trns(ctx.get(), &trns) == 0;
    switch (ihdr.color_type) {
      case SPNG_COLOR_TYPE_GRAYSCALE:
        // Host-order samples at the stored depth; 1-, 2- and 4-bit grey widened (and scaled) to 8 bits.
        format = sixteen ? SPNG_FMT_PNG : ihdr.bit_depth == 8 ? SPNG_FMT_PNG : SPNG_FMT_G8;
        type = sixteen ? CV_16UC1 : CV_8UC1;
        break;
      case SPNG_COLOR_TYPE_TRUECOLOR:
        format = SPNG_FMT_PNG, type = sixteen ? CV_16UC3 : CV_8UC3;
        break;
      case SPNG_COLOR_TYPE_TRUECOLOR_ALPHA:
        format = SPNG_FMT_PNG, type = sixteen ? CV_16UC4 : CV_8UC4;
        break;
      case SPNG_COLOR_TYPE_GRAYSCALE_ALPHA:
        format = sixteen ? SPNG_FMT_RGBA16 : SPNG_FMT_RGBA8, type = sixteen ? CV_16UC4 : CV_8UC4;
        break;
      case SPNG_COLOR_TYPE_INDEXED:
        format = has_trns ? SPNG_FMT_RGBA8 : SPNG_FMT_RGB8, type = has_trns ? CV_8UC4 : CV_8UC3;
        flags = has_trns ? SPNG_DECODE_TRNS : 0;
        break;
      default: return Fail(error, "unknown PNG colour type " + std::to_string(ihdr.color_type));
    }
  }
  size_t size = 0;
  if (int e = spng_decoded_image_size(ctx.get(), format, &size)) return Fail(error, spng_strerror(e));
  cv::Mat image(rows, cols, type);
  if (size != image.total() * image.elemSize())
    return Fail(error, "decoded size " + std::to_string(size) + " bytes does not match " + std::to_string(cols) + "x" +
                           std::to_string(rows));
  if (int e = spng_decode_image(ctx.get(), image.data, size, format, flags))
    return Fail(error, std::string("cannot be decoded (") + spng_strerror(e) + ")");
  ToBgr(image);
  return image;
}

cv::Mat DecodeJpeg(const std::vector<uint8_t>& bytes, ImageDecode mode, std::string* error) {
  Turbo handle(tjInitDecompress());
  if (!handle) return Fail(error, "cannot start the JPEG decoder");
  int width = 0, height = 0, subsampling = 0, colourspace = 0;
  if (tjDecompressHeader3(handle.get(), bytes.data(), static_cast<unsigned long>(bytes.size()), &width, &height,
                          &subsampling, &colourspace) != 0)
    return Fail(error, std::string("not a JPEG (") + tjGetErrorStr2(handle.get()) + ")");
  const bool grey = mode == ImageDecode::kUnchanged && colourspace == TJCS_GRAY;
  cv::Mat image(height, width, grey ? CV_8UC1 : CV_8UC3);
  if (tjDecompress2(handle.get(), bytes.data(), static_cast<unsigned long>(bytes.size()), image.data, width, 0, height,
                    grey ? TJPF_GRAY : TJPF_BGR, 0) != 0 &&
      tjGetErrorCode(handle.get()) == TJERR_FATAL)
    return Fail(error, std::string("cannot be decoded (") + tjGetErrorStr2(handle.get()) + ")");
  return image;
}

std::vector<uint8_t> EncodePng(const cv::Mat& image, int compression_level) {
  const int channels = image.channels(), depth = image.depth();
  if (image.empty() || (depth != CV_8U && depth != CV_16U) || (channels != 1 && channels != 3 && channels != 4))
    throw std::invalid_argument("EncodePng: needs an 8- or 16-bit image of 1, 3 or 4 channels");
  if (compression_level < 0 || compression_level > 9) throw std::invalid_argument("EncodePng: level must be 0-9");
  cv::Mat rgb;
  if (channels == 3) cv::cvtColor(image, rgb, cv::COLOR_BGR2RGB);
  else if (channels == 4) cv::cvtColor(image, rgb, cv::COLOR_BGRA2RGBA);
  else rgb = image.isContinuous() ? image : image.clone();
  Spng ctx(spng_ctx_new(SPNG_CTX_ENCODER));
  if (!ctx) throw std::runtime_error("EncodePng: out of memory");
  spng_ihdr ihdr{};
  ihdr.width = static_cast<uint32_t>(image.cols);
  ihdr.height = static_cast<uint32_t>(image.rows);
  ihdr.bit_depth = depth == CV_16U ? 16 : 8;
  ihdr.color_type = channels == 1   ? SPNG_COLOR_TYPE_GRAYSCALE
                    : channels == 3 ? SPNG_COLOR_TYPE_TRUECOLOR
                                    : SPNG_COLOR_TYPE_TRUECOLOR_ALPHA;
  spng_set_ihdr(ctx.get(), &ihdr);
  spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1);
  spng_set_option(ctx.get(), SPNG_IMG_COMPRESSION_LEVEL, compression_level);
  if (int e = spng_encode_image(ctx.get(), rgb.data, rgb.total() * rgb.elemSize(), SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE))
    throw std::runtime_error(std::string("EncodePng: ") + spng_strerror(e));
  size_t length = 0;
  int e = 0;
  std::unique_ptr<void, decltype(&free)> buffer(spng_get_png_buffer(ctx.get(), &length, &e), &free);
  if (!buffer) throw std::runtime_error(std::string("EncodePng: ") + spng_strerror(e));
  const auto* begin = static_cast<const uint8_t*>(buffer.get());
  return std::vector<uint8_t>(begin, begin + length);
}

std::vector<uint8_t> EncodeJpeg(const cv::Mat& image, int quality) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    throw std::invalid_argument("EncodeJpeg: needs an 8-bit image of 1 or 3 channels");
  if (quality < 1 || quality > 100) throw std::invalid_argument("EncodeJpeg: quality must be 1-100");
  const cv::Mat pixels = image.isContinuous() ? image : image.clone();
  Turbo handle(tjInitCompress());
  if (!handle) throw std::runtime_error("EncodeJpeg: cannot start the JPEG encoder");
  const bool grey = image.channels() == 1;
  unsigned char* out = nullptr;
  unsigned long length = 0;
  if (tjCompress2(handle.get(), pixels.data, pixels.cols, 0, pixels.rows, grey ? TJPF_GRAY : TJPF_BGR, &out, &length,
                  grey ? TJSAMP_GRAY : TJSAMP_420, quality, 0) != 0) {
    tjFree(out);
    throw std::runtime_error(std::string("EncodeJpeg: ") + tjGetErrorStr2(handle.get()));
  }
  std::vector<uint8_t> bytes(out, out + length);
  tjFree(out);
  return bytes;
}

std::vector<uint8_t> ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return {};
  std::vector<uint8_t> bytes(static_cast<size_t>(std::max<std::streamoff>(0, in.tellg())));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()))) return {};
  return bytes;
}

cv::Mat ReadPngFile(const std::string& path, ImageDecode mode) {
  const std::vector<uint8_t> bytes = ReadFileBytes(path);
  if (bytes.empty()) throw std::runtime_error("cannot read image " + path + " (missing or empty)");
  std::string error;
  cv::Mat image = DecodePng(bytes, mode, &error);
  if (image.empty()) throw std::runtime_error("cannot read image " + path + ": " + error);
  return image;
}

void WritePngFile(const std::string& path, const cv::Mat& image, int compression_level) {
  const std::vector<uint8_t> bytes = EncodePng(image, compression_level);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())) || !out.flush())
    throw std::runtime_error("cannot write " + path);
}

}  // namespace dslam
