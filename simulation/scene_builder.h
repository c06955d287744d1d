#pragma once
// Renderable scenes from the real KITTI trajectories and boxes or from the simulator: the camera path,
// a textured road under it, facades on both sides and poles, all generated along the path so that any
// trajectory works; objects as boxes with their true pose per frame.

#include "data/kitti_dataset.h"
#include "data/scene.h"
#include "data/sequence.h"

namespace dslam {

struct StaticWorldOptions {
  double camera_height_m = 1.65;
  double road_half_width_m = 12.0;
  double facade_height_m = 9.0;
  double segment_m = 4.0;  // length of a road / facade piece along the path
  double pole_spacing_m = 24.0;
};

// Road, facade and pole quads along the camera path (and 60 m past its end).
std::vector<StaticQuad> StaticWorldAlongPath(const std::vector<SE3>& T_world_camera, const StaticWorldOptions& options);

Scene SceneFromKitti(const KittiGroundTruthSequence& gt, const StaticWorldOptions& options = {});
// From a simulated sequence's ground truth (objects without a box size, e.g. the paper's ellipsoid, are
// left out).
Scene SceneFromSequence(const Sequence& seq, const StaticWorldOptions& options = {});

}  // namespace dslam
