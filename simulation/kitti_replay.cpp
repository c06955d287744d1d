#include "simulation/kitti_replay.h"

#include <algorithm>
#include <random>

#include "simulation/shapes.h"

namespace dslam {
namespace {

// Facade and road points around a camera pose, in its own frame: x right, y down, z forward.
void AddStaticPointsAround(const SE3& T_world_camera, double z_from, double z_to, double camera_height,
                           std::mt19937_64& rng, std::vector<Vec3>* points) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = z_from + (z_to - z_from) * u(rng);
  for (double side : {-1.0, 1.0})
    points->push_back(T_world_camera * Vec3(side * (9.0 + 4.0 * u(rng)), -5.0 + 6.5 * u(rng), z));
  points->push_back(T_world_camera * Vec3(-8.0 + 16.0 * u(rng), camera_height, z_from + (z_to - z_from) * u(rng)));
}

}  // namespace

SensorSimulator MakeKittiReplaySimulator(const KittiGroundTruthSequence& gt, const KittiReplayOptions& options) {
  SimWorld world;
  world.name = gt.name;
  world.frame_rate_hz = gt.frame_rate_hz;
  world.T_world_camera = gt.T_world_camera;

  // Static structure along the path: a slice every half metre travelled, and slices ahead of the
  // last pose so the end of the sequence sees as much as the rest.
  std::mt19937_64 rng(options.seed * 6364136223846793005ULL + 1442695040888963407ULL);
  constexpr double kSliceM = 0.5;
  double since_last = kSliceM;
  for (size_t k = 0; k < world.T_world_camera.size(); ++k) {
    if (k > 0) since_last += (world.T_world_camera[k].translation() - world.T_world_camera[k - 1].translation()).norm();
    while (since_last >= kSliceM) {
      since_last -= kSliceM;
      AddStaticPointsAround(world.T_world_camera[k], -kSliceM, 0.0, options.camera_height_m, rng,
                            &world.static_points_world);
    }
  }
  for (double z = 0.0; z < 45.0; z += kSliceM)
    AddStaticPointsAround(world.T_world_camera.back(), z, z + kSliceM, options.camera_height_m, rng,
                          &world.static_points_world);

  for (const auto& [id, track] : gt.objects) {
    SimObject obj;
    obj.object_id = id;
    obj.category = track.category;
    // Small objects (pedestrians) get a finer grid so that they still carry enough points.
    const double spacing = std::min(0.3, std::min({track.l, track.w, track.h}) / 3.0);
    obj.surface = SampleBox(track.l, track.w, track.h, spacing);
    obj.centroid_body = Vec3(0.0, -track.h / 2.0, 0.0);  // docs/design.md §10: (X, Y - h/2, Z)
    for (const auto& [k, T_camera_object] : track.T_camera_object)
      obj.L_world_object[k] = gt.T_world_camera[k] * T_camera_object;
    world.objects.push_back(std::move(obj));
  }

  SensorModel sensor;
  sensor.object_max_range_m = options.object_max_range_m;
  if (gt.calibration) {
    sensor.camera.fx = gt.calibration->fx();
    sensor.camera.fy = gt.calibration->fy();
    sensor.camera.cx = gt.calibration->cx();
    sensor.camera.cy = gt.calibration->cy();
  }
  return SensorSimulator(std::move(world), sensor, options.noise, options.seed);
}

Sequence MakeKittiReplay(const KittiGroundTruthSequence& gt, const KittiReplayOptions& options) {
  return MakeKittiReplaySimulator(gt, options).drain();
}

}  // namespace dslam
