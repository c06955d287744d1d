#include "simulation/sensor_simulator.h"

#include <algorithm>
#include <iterator>
#include <memory>
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

}  // namespace

// The static points within `range` of a position, in index order (the order noise is drawn in), through
// a uniform grid of cells `range` wide: a frame looks at 27 cells, not at the whole world.
class SensorSimulator::StaticPointIndex {
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

SensorSimulator::SensorSimulator(SimWorld world, const SensorModel& sensor, const SimNoise& noise, uint64_t seed)
    : name_(world.name), frame_rate_hz_(world.frame_rate_hz), sensor_(sensor), noise_(noise), rng_(seed) {
  noise.validate();
  const int num_frames = static_cast<int>(world.T_world_camera.size());
  if (num_frames < 2) throw std::invalid_argument("a simulated sequence needs at least 2 frames");
  for (const auto& obj : world.objects)
    for (const auto& [k, L] : obj.L_world_object)
      if (k < 0 || k >= num_frames)
        throw std::invalid_argument("object " + std::to_string(obj.object_id) + " has a pose for frame " +
                                    std::to_string(k) + " outside the sequence");

  // World = the first camera frame.
  const SE3 T_new_old = world.T_world_camera.front().inverse();
  for (const SE3& T : world.T_world_camera) gt_.T_world_camera.push_back(T_new_old * T);
  world.T_world_camera = {};
  for (size_t i = 0; i < world.static_points_world.size(); ++i)
    gt_.static_points_world[static_cast<int64_t>(i)] = T_new_old * world.static_points_world[i];
  world.static_points_world = {};
  for (size_t j = 0; j < world.objects.size(); ++j) {
    SimObject& obj = world.objects[j];
    ObjectGroundTruth& o = gt_.objects[obj.object_id];
    o.object_id = obj.object_id;
    o.measurable_frames.emplace();
    o.category = obj.category;
    o.box_lwh = obj.box_lwh;
    for (const auto& [k, L] : obj.L_world_object) {
      o.L_world_object[k] = T_new_old * L;
      o.centroid_world[k] = o.L_world_object[k] * obj.centroid_body;
    }
    for (size_t i = 0; i < obj.surface.size(); ++i)
      gt_.object_points[kObjectTrackBase + static_cast<int64_t>(j) * kTracksPerObject + static_cast<int64_t>(i)] = {
          obj.object_id, obj.surface[i].p_body};
    Body body{obj.object_id, 0, -1, std::move(obj.surface), std::move(obj.occluded_frames)};
    if (!obj.L_world_object.empty())
      body.first_frame = obj.L_world_object.begin()->first, body.last_frame = obj.L_world_object.rbegin()->first;
    obj.L_world_object.clear();  // the ground truth holds the poses: one copy of the world
    bodies_.push_back(std::move(body));
  }
  static_index_ = std::make_unique<StaticPointIndex>(gt_.static_points_world, sensor_.static_max_range_m);
}

SensorSimulator::~SensorSimulator() = default;
SensorSimulator::SensorSimulator(SensorSimulator&&) noexcept = default;

FrameMeasurement SensorSimulator::next() {
  if (done()) throw std::logic_error("the simulated sequence has no frame " + std::to_string(next_frame_));
  const int k = next_frame_++;
  FrameMeasurement frame;
  frame.frame_index = k;
  frame.t_ns = static_cast<int64_t>(k * 1e9 / frame_rate_hz_);
  const SE3 T_camera_world = gt_.T_world_camera[k].inverse();
  if (k > 0) frame.odometry = NoisyOdometry(gt_.T_world_camera[k - 1].inverse() * gt_.T_world_camera[k], noise_, rng_);

  for (int64_t i : static_index_->near(gt_.T_world_camera[k].translation())) {
    const Vec3 p = T_camera_world * gt_.static_points_world.at(i);
    if (p.z() < sensor_.min_depth_m || p.norm() > sensor_.static_max_range_m || !sensor_.camera.inImage(p)) continue;
    frame.static_points.push_back({i, p + GaussianVec3(rng_, noise_.point_sigma_m)});
  }

  for (size_t j = 0; j < bodies_.size(); ++j) {
    Body& body = bodies_[j];
    std::vector<size_t> seen_before;
    seen_before.swap(body.seen_last_frame);  // empty unless measured in frame k-1
    if (k < body.first_frame || k > body.last_frame || body.occluded_frames.count(k)) continue;
    ObjectGroundTruth& o = gt_.objects[body.object_id];
    const auto pose = o.L_world_object.find(k);
    if (pose == o.L_world_object.end()) continue;
    if ((T_camera_world * o.centroid_world.at(k)).norm() >= sensor_.object_max_range_m) continue;
    const SE3 T_camera_object = T_camera_world * pose->second;
    const Vec3 camera_in_object = T_camera_object.inverse().translation();
    ObjectObservation obs;
    obs.object_id = body.object_id;
    std::vector<size_t> seen;
    for (size_t i = 0; i < body.surface.size(); ++i) {
      const SurfacePoint& s = body.surface[i];
      if (s.normal_body.dot(camera_in_object - s.p_body) <= 0.0) continue;  // back face
      const Vec3 p = T_camera_object * s.p_body;
      if (p.z() < sensor_.min_depth_m || !sensor_.camera.inImage(p)) continue;
      obs.points.push_back({kObjectTrackBase + static_cast<int64_t>(j) * kTracksPerObject + static_cast<int64_t>(i),
                            p + GaussianVec3(rng_, noise_.point_sigma_m)});
      seen.push_back(i);
    }
    if (static_cast<int>(obs.points.size()) < sensor_.min_object_points) continue;
    o.observed_frames.insert(k);
    // The pair k-1 -> k is measurable when enough of the same surface points are seen in both frames.
    std::vector<size_t> both;
    std::set_intersection(seen.begin(), seen.end(), seen_before.begin(), seen_before.end(), std::back_inserter(both));
    if (static_cast<int>(both.size()) >= kMinMeasurablePoints) o.measurable_frames->insert(k);
    body.seen_last_frame = std::move(seen);
    frame.objects.push_back(std::move(obs));
  }
  return frame;
}

Sequence SensorSimulator::drain() {
  Sequence seq;
  seq.name = name_;
  seq.frame_rate_hz = frame_rate_hz_;
  while (!done()) seq.frames.push_back(next());
  seq.gt = std::move(gt_);
  return seq;
}

Sequence SimulateSensor(SimWorld world, const SensorModel& sensor, const SimNoise& noise, uint64_t seed) {
  return SensorSimulator(std::move(world), sensor, noise, seed).drain();
}

}  // namespace dslam
