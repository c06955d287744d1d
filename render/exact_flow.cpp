#include "render/exact_flow.h"

#include <cmath>

namespace dslam {

FlowField ExactFlow(const Scene& scene, int k, const RgbdFrame& frame_k, const RgbdFrame& frame_next,
                    const CameraIntrinsics& camera) {
  FlowField flow;
  flow.width = frame_k.width, flow.height = frame_k.height;
  flow.uv.assign(static_cast<size_t>(flow.width) * flow.height * 2, 1e10f);
  const SE3 T_next_k = scene.T_world_camera[k + 1].inverse() * scene.T_world_camera[k];
  // Per object: its motion seen from camera k to camera k+1, T_next_world * L_next * L_k^-1 * T_world_k.
  std::map<int, SE3> T_next_k_of_object;
  for (const SceneObject& o : scene.objects) {
    const auto a = o.L_world_object.find(k), b = o.L_world_object.find(k + 1);
    if (a == o.L_world_object.end() || b == o.L_world_object.end()) continue;
    T_next_k_of_object[o.object_id] =
        scene.T_world_camera[k + 1].inverse() * b->second * a->second.inverse() * scene.T_world_camera[k];
  }
  for (int v = 0; v < flow.height; ++v)
    for (int u = 0; u < flow.width; ++u) {
      const float z = frame_k.depth(u, v);
      if (!(z > 0.0f)) continue;
      const Vec3 p_k((u - camera.cx) / camera.fx * z, (v - camera.cy) / camera.fy * z, z);
      const int id = frame_k.id(u, v);
      const SE3* T = &T_next_k;
      if (id != 0) {
        const auto it = T_next_k_of_object.find(id);
        if (it == T_next_k_of_object.end()) continue;
        T = &it->second;
      }
      const Vec3 p_next = *T * p_k;
      if (p_next.z() < camera.near_m) continue;
      const double u_next = camera.fx * p_next.x() / p_next.z() + camera.cx;
      const double v_next = camera.fy * p_next.y() / p_next.z() + camera.cy;
      const int ui = static_cast<int>(std::lround(u_next)), vi = static_cast<int>(std::lround(v_next));
      if (ui < 0 || vi < 0 || ui >= flow.width || vi >= flow.height) continue;
      // Visible there: the next frame sees this surface (within 2 % and 5 cm), not something in front of it.
      const float z_seen = frame_next.depth(ui, vi);
      if (!(z_seen > 0.0f) || std::abs(z_seen - p_next.z()) > 0.05 + 0.02 * p_next.z()) continue;
      if (frame_next.id(ui, vi) != id) continue;
      const size_t i = 2 * (static_cast<size_t>(v) * flow.width + u);
      flow.uv[i] = static_cast<float>(u_next - u);
      flow.uv[i + 1] = static_cast<float>(v_next - v);
    }
  return flow;
}

}  // namespace dslam
