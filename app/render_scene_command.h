#pragma once

#include <ostream>
#include <string>

namespace dslam {

// KITTI's nominal baseline between its colour cameras (P2, P3), used when no calibration gives one.
constexpr double kKittiStereoBaselineM = 0.54;

struct RenderSceneOptions {
  std::string kitti_dir;   // KITTI tracking data (either layout), or
  std::string sequence;    // e.g. 0000
  std::string scenario;    // a simulator scenario with box objects ("city")
  int frames = 0;          // 0: the whole sequence
  double scale = 1.0;      // image size and intrinsics relative to KITTI's 1242x375
  std::string out_dir = "results/render";
  double image_noise = 0.0;             // colour noise sigma, grey levels
  double depth_noise_m = 0.0;           // depth noise sigma at zero depth
  double depth_noise_per_m2 = 0.0;      // ... plus this per square metre of depth
  uint64_t seed = 1;
  bool stereo = false;      // also the right camera (image_1/, P3): the sequence's baseline, else 0.54 m
  bool exact_flow = false;  // also the exact forward flow (flow/NNNNNN.flo, 3.7 MB a KITTI-sized frame)
  bool quiet = false;
};

// `dslam render-scene`: renders a KITTI-driven scene into the VDO-SLAM layout with exact ground truth.
// Exit codes: 0 done, 2 bad input, 3 no display to be had.
int RunRenderSceneCommand(const RenderSceneOptions& options, std::ostream& out, std::ostream& err);

}  // namespace dslam
