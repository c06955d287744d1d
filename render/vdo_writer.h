#pragma once
// Writes rendered frames and their exact ground truth in the VDO-SLAM / DynoSAM layout:
//   image_0/NNNNNN.png (colour), depth/NNNNNN.png (16-bit depth in millimetres, 0 = none),
//   mask/NNNNNN.png (16-bit instance ids), semantic/NNNNNN.txt (VDO text masks),
//   pose_gt.txt, object_pose.txt, object_category.txt, times.txt, calib.txt (odometry.txt: render-scene).

#include <fstream>
#include <string>

#include "data/scene.h"
#include "render/rgbd_renderer.h"

namespace dslam {

class VdoWriter {
 public:
  VdoWriter(const std::string& dir, const Scene& scene, const CameraIntrinsics& camera);
  // Frame k: the images, its camera pose and the pose and 2D box of every object seen in the mask.
  void write(int k, const RgbdFrame& frame);

 private:
  std::string dir_;
  const Scene& scene_;
  CameraIntrinsics camera_;
  std::ofstream poses_, objects_, times_;
};

}  // namespace dslam
