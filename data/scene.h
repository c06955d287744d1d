#pragma once
// A renderable world: camera path, static textured quads and boxes with their poses per frame.
// Plain data (no renderer types) so that scene builders live in the core.

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "geometry/se3.h"

namespace dslam {

struct StaticQuad {
  std::array<Vec3, 4> corners_world;  // in order around the quad
  uint32_t texture_seed = 1;
};

struct SceneObject {
  int object_id = 1;  // 1..65535
  std::string category = "VEHICLE";
  double l = 4.0, w = 1.7, h = 1.5;   // KITTI box: l along x, h up (-y) from the bottom centre, w along z
  std::map<int, SE3> L_world_object;  // frames in which it exists
  uint32_t texture_seed = 1;
};

struct Scene {
  std::string name;
  double frame_rate_hz = 10.0;
  std::vector<SE3> T_world_camera;  // world = first camera frame
  std::vector<StaticQuad> static_quads;
  std::vector<SceneObject> objects;
};

}  // namespace dslam
