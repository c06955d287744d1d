#pragma once
// Off-screen RGB-D rendering with exact ground truth: colour, metric depth and instance masks of a
// world of textured static quads (road, facades) and textured boxes (vehicles, pedestrians), seen by
// a pinhole camera with given intrinsics. Needs an X display (hold a HeadlessDisplay).

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "data/scene.h"
#include "geometry/se3.h"

namespace dslam {

struct CameraIntrinsics {
  int width = 1242, height = 375;
  double fx = 721.5377, fy = 721.5377, cx = 609.5593, cy = 172.854;  // KITTI's P2
  double near_m = 0.5, far_m = 200.0;
};

// A textured planar quad: corners in order around the quad, world frame.
using RenderQuad = StaticQuad;

// A box in the KITTI body convention (origin at the bottom centre, l along x, h upwards along -y, w along z).
struct RenderBox {
  int object_id = 1;  // 1..65535, written into the instance mask
  SE3 L_world_object;
  double l = 4.0, w = 1.7, h = 1.5;
  uint32_t texture_seed = 1;
};

struct RgbdFrame {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;        // row-major from the top-left pixel, 3 bytes a pixel
  std::vector<float> depth_m;      // z in the camera frame; 0 where nothing was hit
  std::vector<uint16_t> instance;  // object id; 0 = background
  float depth(int u, int v) const { return depth_m[static_cast<size_t>(v) * width + u]; }
  uint16_t id(int u, int v) const { return instance[static_cast<size_t>(v) * width + u]; }
};

class RgbdRenderer {
 public:
  RgbdRenderer(const CameraIntrinsics& camera, const std::vector<RenderQuad>& static_world);
  ~RgbdRenderer();
  RgbdRenderer(const RgbdRenderer&) = delete;
  RgbdRenderer& operator=(const RgbdRenderer&) = delete;

  RgbdFrame render(const SE3& T_world_camera, const std::vector<RenderBox>& objects);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dslam
