#include "simulation/sensor_simulator.h"

#include <algorithm>
#include <random>
#include <unordered_map>
#include <stdexcept>

namespace dslam {
namespace {
constexpr int64_t kObjectTrackBase = 1'000'000;
constexpr int64_t kTracksPerObject = 100'000;

Vec3 GaussianVec3(std::mt19937_64& rng, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  return Vec3(n(rng), n(rng), n(rng));
}

// The static points within `range` of a position, in index order (the order noise is drawn in), through
// a uniform grid of cells `range` wide: a frame looks at 27 cells, not at the whole world.
class StaticPointIndex {
 public:
  StaticPointIndex(const std::unordered_map<int64_t, Vec3>& points_world, double range) : cell_(range) {
    for (const auto& [id, p] : points_world) cells_[key(cellOf(p))].push_back(id);
  }
  std::vector<int64_t> near(const Vec3& position) const {
    std::vector<int64_t> out;
    const Eigen::Vector3i c = cellOf(position);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it != cells_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
        }
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  Eigen::Vector3i cellOf(const Vec3& p) const { return (p / cell_).array().floor().cast<int>(); }
  static int64_t key(const Eigen::Vector3i& c) {
    return (static_cast<int64_t>(c.x()) * 2'000'003 + c.y()) * 2'000'003 + c.z();
  }
  double cell_;
  std::unordered_map<int64_t, std::vector<int64_t>> cells_;
};

}  // namespace

OdometryMeasurement NoisyOdometry(const SE3& T_prev_curr_true, const SimNoise& noise, std::mt19937_64& rng) {
  OdometryMeasurement odom;
  const double sigma_t =
      std::max(noise.odom_translation_floor_m, noise.odom_translation_fraction * T_prev_curr_true.translation().norm());
  const double sigma_r = std::max(noise.odom_rotation_floor_rad, noise.odom_rotation_fraction * T_prev_curr_true.angle());
  odom.sigma << Vec3::Constant(sigma_t), Vec3::Constant(sigma_r);
  Vec6 xi;
  xi << GaussianVec3(rng, sigma_t), GaussianVec3(rng, sigma_r);
  odom.T_prev_curr = T_prev_curr_true * SE3::Exp(xi);
  return odom;
}

void SimNoise::validate() const {
  if (!(point_sigma_m >= 0.0)) throw std::invalid_argument("point sigma must be >= 0");
  if (!(odom_translation_fraction >= 0.0) || !(odom_rotation_fraction >= 0.0))
    throw std::invalid_argument("odometry noise fractions must be >= 0");
  if (!(odom_translation_floor_m > 0.0) || !(odom_rotation_floor_rad > 0.0))
    throw std::invalid_argument("odometry noise floors must be positive");
}

Sequence SimulateSensor(const SimWorld& world, const SensorModel& sensor, const SimNoise& noise, uint64_t seed) {
  noise.validate();
  const int num_frames = static_cast<int>(world.T_world_camera.size());
  if (num_frames < 2) throw std::invalid_argument("a simulated sequence needs at least 2 frames");
  for (const auto& obj : world.objects)
    for (const auto& [k, L] : obj.L_world_object)
      if (k < 0 || k >= num_frames)
        throw std::invalid_argument("object " + std::to_string(obj.object_id) + " has a pose for frame " +
                                    std::to_string(k) + " outside the sequence");

  std::mt19937_64 rng(seed);
  // World = the first camera frame.
  const SE3 T_new_old = world.T_world_camera.front().inverse();

  Sequence seq;
  seq.name = world.name;
  seq.frame_rate_hz = world.frame_rate_hz;
  GroundTruth& gt = seq.gt;
  for (const SE3& T : world.T_world_camera) gt.T_world_camera.push_back(T_new_old * T);
  for (size_t i = 0; i < world.static_points_world.size(); ++i)
    gt.static_points_world[static_cast<int64_t>(i)] = T_new_old * world.static_points_world[i];
  for (size_t j = 0; j < world.objects.size(); ++j) {
    const SimObject& obj = world.objects[j];
    ObjectGroundTruth& o = gt.objects[obj.object_id];
    o.object_id = obj.object_id;
    o.category = obj.category;
    o.box_lwh = obj.box_lwh;
    for (const auto& [k, L] : obj.L_world_object) {
      o.L_world_object[k] = T_new_old * L;
      o.centroid_world[k] = o.L_world_object[k] * obj.centroid_body;
    }
    for (size_t i = 0; i < obj.surface.size(); ++i)
      gt.object_points[kObjectTrackBase + static_cast<int64_t>(j) * kTracksPerObject + static_cast<int64_t>(i)] = {
          obj.object_id, obj.surface[i].p_body};
  }

  const StaticPointIndex static_index(gt.static_points_world, sensor.static_max_range_m);
  for (int k = 0; k < num_frames; ++k) {
    FrameMeasurement frame;
    frame.frame_index = k;
    frame.t_ns = static_cast<int64_t>(k * 1e9 / world.frame_rate_hz);
    const SE3 T_camera_world = gt.T_world_camera[k].inverse();
    if (k > 0) frame.odometry = NoisyOdometry(gt.T_world_camera[k - 1].inverse() * gt.T_world_camera[k], noise, rng);

    for (int64_t i : static_index.near(gt.T_world_camera[k].translation())) {
      const Vec3 p = T_camera_world * gt.static_points_world.at(i);
      if (p.z() < sensor.min_depth_m || p.norm() > sensor.static_max_range_m || !sensor.camera.inImage(p)) continue;
      frame.static_points.push_back({i, p + GaussianVec3(rng, noise.point_sigma_m)});
    }

    for (size_t j = 0; j < world.objects.size(); ++j) {
      const SimObject& obj = world.objects[j];
      if (obj.L_world_object.empty() || k < obj.L_world_object.begin()->first || k > obj.L_world_object.rbegin()->first)
        continue;
      ObjectGroundTruth& o = gt.objects[obj.object_id];
      if (obj.occluded_frames.count(k) || !o.L_world_object.count(k)) continue;
      if ((T_camera_world * o.centroid_world[k]).norm() >= sensor.object_max_range_m) continue;
      const SE3 T_camera_object = T_camera_world * o.L_world_object[k];
      const Vec3 camera_in_object = T_camera_object.inverse().translation();
      ObjectObservation obs;
      obs.object_id = obj.object_id;
      for (size_t i = 0; i < obj.surface.size(); ++i) {
        const SurfacePoint& s = obj.surface[i];
        if (s.normal_body.dot(camera_in_object - s.p_body) <= 0.0) continue;  // back face
        const Vec3 p = T_camera_object * s.p_body;
        if (p.z() < sensor.min_depth_m || !sensor.camera.inImage(p)) continue;
        obs.points.push_back({kObjectTrackBase + static_cast<int64_t>(j) * kTracksPerObject + static_cast<int64_t>(i),
                              p + GaussianVec3(rng, noise.point_sigma_m)});
      }
      if (static_cast<int>(obs.points.size()) < sensor.min_object_points) continue;
      o.observed_frames.insert(k);
      frame.objects.push_back(std::move(obs));
    }
    seq.frames.push_back(std::move(frame));
  }
  return seq;
}

}  // namespace dslam
