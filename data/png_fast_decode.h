#pragma once
// The PNGs dslam reads by the thousand, camera images, depth and instance masks (8-bit grey, RGB or RGBA and
// 16-bit grey, not interlaced), decoded without libpng: the chunks are walked and checksummed here, the image
// data inflated by libdeflate (twice as fast as zlib, which libpng calls row by row) and the rows' filters
// undone with SIMD (data/png_unfilter.h). A demo frame's colour image decodes in about half libpng's time.
// Every other PNG, and any PNG this path finds unusual, is left to libpng, which decodes it or says what is wrong.

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "data/image_codec.h"

namespace dslam {

// True with *image decoded as DecodePng decodes it (the same pixels, OpenCV's layouts) when `bytes` are a PNG of
// a layout above and are sound. False, *image untouched, for any other PNG or when something is unusual: other
// bit depths or colour types, interlacing, a critical chunk other than IHDR, IDAT and IEND (a palette, an
// unknown one), IDAT chunks not consecutive, a checksum that fails, image data that does not inflate to exactly
// the image's rows, a filter byte that is not one of PNG's five. The one PNG this path takes that libpng
// would refuse: image data referring back further than its zlib header's window (it is decoded correctly).
bool DecodeCommonPng(const std::vector<uint8_t>& bytes, ImageDecode mode, cv::Mat* image);

}  // namespace dslam
