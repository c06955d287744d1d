#pragma once
// Per-pixel inputs of the VDO-SLAM layout, without OpenCV: Middlebury .flo optical flow and the
// semantic/*.txt instance masks. Errors throw std::runtime_error naming the file (and line).

#include <cstdint>
#include <string>
#include <vector>

namespace dslam {

struct FlowField {
  int width = 0, height = 0;
  std::vector<float> uv;  // row-major, (u, v) per pixel, pixels
  float u(int x, int y) const { return uv[2 * (static_cast<size_t>(y) * width + x)]; }
  float v(int x, int y) const { return uv[2 * (static_cast<size_t>(y) * width + x) + 1]; }
};
// Middlebury .flo: "PIEH" (float 202021.25), int32 width, int32 height, width*height*2 float32.
FlowField ReadFlo(const std::string& path);
// The same into `uv` (width*height*2 floats, e.g. a CV_32FC2 image's data), without a copy: throws naming the
// file when its size is not width x height.
void ReadFloInto(const std::string& path, int width, int height, float* uv);
// Writes `flow` whole (a temporary file renamed), so that a reader never sees half of one. Unknown flow (no
// surface, hidden in the next frame) follows Middlebury: a component above kUnknownFlow (ExactFlow writes 1e10).
void WriteFlo(const std::string& path, const FlowField& flow);
// Middlebury's threshold of unknown flow: a component above it means "no flow here".
constexpr float kUnknownFlow = 1e9f;

struct InstanceMask {
  int width = 0, height = 0;
  std::vector<int32_t> ids;  // row-major; 0 = background (negative values kept as read)
  int32_t at(int x, int y) const { return ids[static_cast<size_t>(y) * width + x]; }
};
// VDO-SLAM semantic/*.txt: one text row of integers per image row, all rows the same length.
InstanceMask ReadSemanticTxt(const std::string& path);

}  // namespace dslam
