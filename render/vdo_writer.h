#pragma once
// Writes rendered frames and their exact ground truth in the VDO-SLAM / DynoSAM layout:
//   image_0/NNNNNN.png (colour), depth/NNNNNN.png (16-bit depth in millimetres, 0 = none),
//   mask/NNNNNN.png (16-bit instance ids), semantic/NNNNNN.txt (VDO text masks),
//   pose_gt.txt, object_pose.txt, object_category.txt, times.txt, calib.txt (odometry.txt: render-scene);
//   with a stereo baseline also image_1/NNNNNN.png (the right camera, P3 in calib.txt), and on request the
//   exact forward flow flow/NNNNNN.flo (frame k to k+1, render/exact_flow.h).

#include <fstream>
#include <string>

#include "data/dense_maps.h"
#include "data/scene.h"
#include "render/rgbd_renderer.h"

namespace dslam {

class VdoWriter {
 public:
  // `stereo_baseline_m` > 0: a right camera that far along the left camera's x (KITTI: 0.54 m).
  VdoWriter(const std::string& dir, const Scene& scene, const CameraIntrinsics& camera, double stereo_baseline_m = 0.0);
  // Frame k: the images (`right`: the right camera's colour, with a stereo baseline), its camera pose and
  // the pose and 2D box of every object seen in the mask.
  void write(int k, const RgbdFrame& frame, const RgbdFrame* right = nullptr);
  // The flow from frame k to k+1.
  void writeFlow(int k, const FlowField& flow);

 private:
  std::string dir_;
  const Scene& scene_;
  CameraIntrinsics camera_;
  double stereo_baseline_m_;
  std::ofstream poses_, objects_, times_;
};

}  // namespace dslam
