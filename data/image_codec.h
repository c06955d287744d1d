#pragma once
// PNG and JPEG to and from OpenCV images, through libpng (libdeflate for the common PNGs) and libjpeg-turbo.
// OpenCV's own codecs (imgcodecs) load GDAL and ~110 other libraries into every process that links them, ~0.1 s
// of start-up each time; these libraries (imgcodecs itself uses the first and the last for these formats) are
// all dslam's datasets, results and compressed DDS images need.
// Pixel layouts are OpenCV's: colour is BGR(A), 16-bit samples in host order.

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace dslam {

enum class ImageDecode {
  kUnchanged,  // as stored: 1 channel (8 or 16 bits), 3 (BGR) or 4 (BGRA); palettes become BGR(A)
  kColour,     // always 8-bit BGR (grey replicated, alpha dropped, 16-bit samples to their high byte)
};

// Empty image and *error set (when error is non-null) when the bytes are not a whole, decodable image.
// DecodePng takes the common layouts by its own faster path (data/png_fast_decode.h) and every other PNG, or
// one that path finds unusual, through libpng; DecodePngByLibpng is libpng alone (the tests compare the two).
cv::Mat DecodePng(const std::vector<uint8_t>& bytes, ImageDecode mode, std::string* error = nullptr);
cv::Mat DecodePngByLibpng(const std::vector<uint8_t>& bytes, ImageDecode mode, std::string* error = nullptr);
cv::Mat DecodeJpeg(const std::vector<uint8_t>& bytes, ImageDecode mode, std::string* error = nullptr);

// How rows are predicted before compression. kAdaptive: libpng picks one of PNG's five filters per row (best for
// camera images). kNone: rows stored as they are: for drawn or rendered images (flat areas, sharp edges) the
// files come out about as small, twice as fast to write and 40 % faster to read (docs/benchmarks.md, Pipeline).
enum class PngFilter { kAdaptive, kNone };

// 8- or 16-bit images of 1, 3 (BGR) or 4 (BGRA) channels; compression level 0 (none) to 9. Throws
// std::invalid_argument for other types.
std::vector<uint8_t> EncodePng(const cv::Mat& image, int compression_level = 3,
                               PngFilter filter = PngFilter::kAdaptive);
// 8-bit images of 1 or 3 (BGR) channels, quality 1-100 (colour subsampled 4:2:0). Throws
// std::invalid_argument for other types.
std::vector<uint8_t> EncodeJpeg(const cv::Mat& image, int quality = 90);

// The file's bytes (empty when it cannot be read).
std::vector<uint8_t> ReadFileBytes(const std::string& path);
// Decodes a PNG file; throws std::runtime_error naming the file and what is wrong.
cv::Mat ReadPngFile(const std::string& path, ImageDecode mode = ImageDecode::kUnchanged);
// Encodes and writes a PNG file; throws std::runtime_error naming the file when it cannot be written.
void WritePngFile(const std::string& path, const cv::Mat& image, int compression_level = 3,
                  PngFilter filter = PngFilter::kAdaptive);

}  // namespace dslam
