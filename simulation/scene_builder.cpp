#include "simulation/scene_builder.h"

#include <cmath>

namespace dslam {
namespace {
// Corners of an axis-aligned rectangle of the camera frame (x lateral, y down, z forward) in the world.
StaticQuad Quad(const SE3& T, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, uint32_t seed) {
  return StaticQuad{{T * a, T * b, T * c, T * d}, seed};
}
}  // namespace

std::vector<StaticQuad> StaticWorldAlongPath(const std::vector<SE3>& poses, const StaticWorldOptions& o) {
  std::vector<StaticQuad> quads;
  if (poses.empty()) return quads;
  // Frames along the path every segment_m (a still camera adds nothing), then straight on past the end.
  std::vector<SE3> stations = {poses.front()};
  for (const auto& T : poses)
    if ((T.translation() - stations.back().translation()).norm() >= o.segment_m) stations.push_back(T);
  for (double z = o.segment_m; z <= 60.0; z += o.segment_m)
    stations.push_back(poses.back() * SE3(Eigen::Quaterniond::Identity(), Vec3(0.0, 0.0, z)));
  const double y0 = o.camera_height_m, yt = o.camera_height_m - o.facade_height_m, hw = o.road_half_width_m;
  // Each piece spans half a segment behind to a little more than half ahead of its station, so that
  // consecutive pieces overlap on curves and leave no gap.
  const double back = -0.5 * o.segment_m - 0.3, ahead = 0.5 * o.segment_m + 0.3;
  uint32_t seed = 101;
  double since_pole = o.pole_spacing_m;
  for (size_t i = 0; i < stations.size(); ++i) {
    const SE3& T = stations[i];
    quads.push_back(Quad(T, {-hw, y0, back}, {hw, y0, back}, {hw, y0, ahead}, {-hw, y0, ahead}, seed++));
    for (double side : {-1.0, 1.0})
      quads.push_back(Quad(T, {side * hw, y0, back}, {side * hw, y0, ahead}, {side * hw, yt, ahead},
                           {side * hw, yt, back}, seed++));
    since_pole += i == 0 ? 0.0 : o.segment_m;
    if (since_pole >= o.pole_spacing_m) {  // a pole on each side: four faces of 0.3 m
      since_pole = 0.0;
      for (double side : {-1.0, 1.0}) {
        const double x0 = side * (hw - 2.0) - 0.15, x1 = x0 + 0.3, ph = y0 - 6.0;
        quads.push_back(Quad(T, {x0, y0, -0.15}, {x1, y0, -0.15}, {x1, ph, -0.15}, {x0, ph, -0.15}, 7));
        quads.push_back(Quad(T, {x0, y0, 0.15}, {x1, y0, 0.15}, {x1, ph, 0.15}, {x0, ph, 0.15}, 7));
        quads.push_back(Quad(T, {x0, y0, -0.15}, {x0, y0, 0.15}, {x0, ph, 0.15}, {x0, ph, -0.15}, 7));
        quads.push_back(Quad(T, {x1, y0, -0.15}, {x1, y0, 0.15}, {x1, ph, 0.15}, {x1, ph, -0.15}, 7));
      }
    }
  }
  return quads;
}

Scene SceneFromKitti(const KittiGroundTruthSequence& gt, const StaticWorldOptions& options) {
  Scene scene;
  scene.name = gt.name;
  scene.frame_rate_hz = gt.frame_rate_hz;
  scene.T_world_camera = gt.T_world_camera;
  scene.static_quads = StaticWorldAlongPath(gt.T_world_camera, options);
  for (const auto& [id, track] : gt.objects) {
    SceneObject obj;
    obj.object_id = id;
    obj.category = track.category;
    obj.l = track.l, obj.w = track.w, obj.h = track.h;
    obj.texture_seed = 1000 + static_cast<uint32_t>(id);
    for (const auto& [k, T_camera_object] : track.T_camera_object)
      obj.L_world_object[k] = gt.T_world_camera[k] * T_camera_object;
    scene.objects.push_back(std::move(obj));
  }
  return scene;
}

Scene SceneFromSequence(const Sequence& seq, const StaticWorldOptions& options) {
  Scene scene;
  scene.name = seq.name;
  scene.frame_rate_hz = seq.frame_rate_hz;
  scene.T_world_camera = seq.gt.T_world_camera;
  scene.static_quads = StaticWorldAlongPath(seq.gt.T_world_camera, options);
  for (const auto& [id, o] : seq.gt.objects) {
    if (!o.box_lwh) continue;
    SceneObject obj;
    obj.object_id = id;
    obj.category = o.category;
    obj.l = o.box_lwh->x(), obj.w = o.box_lwh->y(), obj.h = o.box_lwh->z();
    obj.texture_seed = 1000 + static_cast<uint32_t>(id);
    obj.L_world_object = o.L_world_object;
    scene.objects.push_back(std::move(obj));
  }
  return scene;
}

}  // namespace dslam
