#include "data/image_codec.h"
#include "data/png_check.h"
#include "data/png_fast_decode.h"

#include <png.h>
#include <turbojpeg.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace dslam {
namespace {

struct TurboDeleter {
  void operator()(void* handle) const { tjDestroy(handle); }
};
using Turbo = std::unique_ptr<void, TurboDeleter>;

cv::Mat Fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return {};
}

// libpng reports errors through longjmp to the setjmp of the function that called it; the message is kept
// here first. Only plain data lives across those setjmp points.
struct PngErrors {
  char message[256] = "";
};

void PngError(png_structp png, png_const_charp message) {
  auto* errors = static_cast<PngErrors*>(png_get_error_ptr(png));
  std::snprintf(errors->message, sizeof(errors->message), "%s", message);
  png_longjmp(png, 1);
}

void PngWarning(png_structp, png_const_charp) {}  // not printed: the caller reports what matters

struct PngSource {
  const uint8_t* data;
  size_t size;
  size_t at;
};

void ReadFromMemory(png_structp png, png_bytep out, png_size_t length) {
  auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
  if (length > source->size - source->at) png_error(png, "PNG cut off");
  std::memcpy(out, source->data + source->at, length);
  source->at += length;
}

void WriteToVector(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + length);
}

void FlushNothing(png_structp) {}

// Decodes into *image (allocated here, from the header); false with errors->message set on failure.
bool DecodePngInto(const std::vector<uint8_t>& bytes, ImageDecode mode, cv::Mat* image, PngErrors* errors) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, errors, PngError, PngWarning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  std::vector<png_bytep> rows;  // sized before any call that can fail after it
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    return false;
  }
  PngSource source{bytes.data(), bytes.size(), 0};
  png_set_read_fn(png, &source, ReadFromMemory);
  // Damage to the stored bytes fails the chunks' CRC, which libpng checks; zlib's Adler-32 over the inflated
  // rows would only say the same again (1.4 % of a demo run's CPU).
  png_set_option(png, PNG_IGNORE_ADLER32, PNG_OPTION_ON);
  png_read_info(png, info);
  const int bit_depth = png_get_bit_depth(png, info), colour_type = png_get_color_type(png, info);
  const bool trns = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
  // OpenCV's layouts (the transforms its own decoder asks libpng for): BGR(A), 16-bit samples in host order.
  if (colour_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (colour_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (mode == ImageDecode::kColour) {
    if (bit_depth == 16) png_set_strip_16(png);
    if (colour_type == PNG_COLOR_TYPE_GRAY || colour_type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
    if (colour_type & PNG_COLOR_MASK_ALPHA) png_set_strip_alpha(png);
  } else {
    if (bit_depth == 16) png_set_swap(png);
    if (colour_type == PNG_COLOR_TYPE_PALETTE && trns) png_set_tRNS_to_alpha(png);
    if (colour_type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
  }
  png_set_bgr(png);
  png_read_update_info(png, info);
  const int channels = png_get_channels(png, info), depth = png_get_bit_depth(png, info);
  const int rows_count = static_cast<int>(png_get_image_height(png, info));
  const int cols = static_cast<int>(png_get_image_width(png, info));
  *image = cv::Mat(rows_count, cols, CV_MAKETYPE(depth == 16 ? CV_16U : CV_8U, channels));
  if (png_get_rowbytes(png, info) != image->step[0]) png_error(png, "unexpected row size after the transforms");
  rows.resize(static_cast<size_t>(rows_count));
  for (int v = 0; v < rows_count; ++v) rows[static_cast<size_t>(v)] = image->ptr<png_byte>(v);
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}


}  // namespace

cv::Mat DecodePng(const std::vector<uint8_t>& bytes, ImageDecode mode, std::string* error) {
  cv::Mat image;
  if (DecodeCommonPng(bytes, mode, &image)) return image;
  return DecodePngByLibpng(bytes, mode, error);
}

cv::Mat DecodePngByLibpng(const std::vector<uint8_t>& bytes, ImageDecode mode, std::string* error) {
  if (!HasPngSignature(bytes)) return Fail(error, "not a PNG (no PNG signature)");
  cv::Mat image;
  PngErrors errors;
  if (!DecodePngInto(bytes, mode, &image, &errors))
    return Fail(error, std::string("cannot be decoded (") + (*errors.message ? errors.message : "out of memory") + ")");
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

std::vector<uint8_t> EncodePng(const cv::Mat& image, int compression_level, PngFilter filter) {
  const int channels = image.channels(), depth = image.depth();
  if (image.empty() || (depth != CV_8U && depth != CV_16U) || (channels != 1 && channels != 3 && channels != 4))
    throw std::invalid_argument("EncodePng: needs an 8- or 16-bit image of 1, 3 or 4 channels");
  if (compression_level < 0 || compression_level > 9) throw std::invalid_argument("EncodePng: level must be 0-9");
  std::vector<uint8_t> out;
  out.reserve(image.total() * image.elemSize() / 2 + 1024);
  std::vector<png_bytep> rows(static_cast<size_t>(image.rows));
  for (int v = 0; v < image.rows; ++v) rows[static_cast<size_t>(v)] = const_cast<png_bytep>(image.ptr<png_byte>(v));
  PngErrors errors;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &errors, PngError, PngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, info ? &info : nullptr);
    throw std::runtime_error(std::string("EncodePng: ") + (*errors.message ? errors.message : "out of memory"));
  }
  png_set_write_fn(png, &out, WriteToVector, FlushNothing);
  png_set_compression_level(png, compression_level);
  if (filter == PngFilter::kNone) png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows),
               depth == CV_16U ? 16 : 8,
               channels == 1 ? PNG_COLOR_TYPE_GRAY : channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_set_bgr(png);
  if (depth == CV_16U) png_set_swap(png);
  png_write_image(png, rows.data());
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return out;
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

void WritePngFile(const std::string& path, const cv::Mat& image, int compression_level, PngFilter filter) {
  const std::vector<uint8_t> bytes = EncodePng(image, compression_level, filter);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())) || !out.flush())
    throw std::runtime_error("cannot write " + path);
}

}  // namespace dslam
