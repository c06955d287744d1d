#pragma once
// A PNG's structure checked before it is decoded: the signature, the header's size against a bound, and
// every chunk whole up to IEND. A truncated or oversized file is then refused with our own one-line message
// and without allocating its pixels (libpng would print its own line first, and a 20000x20000 image takes
// seconds and gigabytes to refuse). Chunk checksums are left to the decoder.

#include <cstdint>
#include <string>
#include <vector>

namespace dslam {

// Empty when `bytes` (a whole file) are not a PNG (other formats go to the decoder as they are) or are a whole
// PNG of at most `max_pixels`; otherwise what is wrong, e.g. "PNG cut off in chunk IDAT at byte 20000 (...)".
std::string FindPngProblem(const std::vector<unsigned char>& bytes, int64_t max_pixels);

}  // namespace dslam
