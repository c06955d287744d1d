#include "simulation/scenarios.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "simulation/kinematics.h"
#include "simulation/shapes.h"

namespace dslam {
namespace {
constexpr double kFps = 10.0;
constexpr double kGroundY = 1.65;  // camera height above the road (y points down)

SimWorld PaperWorld(int frames) {
  SimWorld world;
  world.name = "paper";
  world.frame_rate_hz = kFps;
  // Camera and object share the centre of their circles and their angular rate, the object 25 degrees
  // ahead on a smaller circle: a constant world-frame pose change H, object always in view.
  const double yaw_rate = 2.0 * kDegToRad * kFps, camera_radius = 20.0, object_radius = 18.0;
  const double lead = 25.0 * kDegToRad;
  const Vec3 centre(camera_radius, 0.0, 0.0);
  SimObject obj;
  obj.object_id = 1;
  obj.category = "ELLIPSOID";
  const double a = 2.2, b = 0.8, c = 1.0;
  obj.surface = SampleEllipsoid(a, b, c, 300);
  const double centre_y = kGroundY - b - 0.1;
  for (int k = 0; k < frames; ++k) {
    const double angle = yaw_rate * k / kFps;
    const GroundPose cam{centre.x() - camera_radius * std::cos(angle), camera_radius * std::sin(angle), angle};
    world.T_world_camera.push_back(CameraPoseOnGround(cam));
    const double oa = angle + lead;
    const GroundPose o{centre.x() - object_radius * std::cos(oa), object_radius * std::sin(oa), oa};
    // Ellipsoid body frame: centre at the origin, long axis along the heading.
    const SE3 L = VehiclePoseOnGround(o, centre_y);
    obj.L_world_object[k] = L;
  }
  world.objects.push_back(std::move(obj));
  return world;
}

// Speed profile pieces for the city cars.
double Ramp(double t, double t0, double v0, double accel, double v_end) {
  if (t < t0) return v0;
  const double v = v0 + accel * (t - t0);
  return accel >= 0.0 ? std::min(v, v_end) : std::max(v, v_end);
}

// Frames [first, last) whose camera is within `range_m` of road position z along the road (the
// camera path's z grows monotonically: the city's weave never turns it back).
std::pair<int, int> FramesNear(const std::vector<GroundPose>& camera_path, int frames, double z, double range_m) {
  const auto begin = camera_path.begin(), end = camera_path.begin() + frames;
  auto by_z = [](const GroundPose& p, double value) { return p.z < value; };
  const int first = static_cast<int>(std::lower_bound(begin, end, z - range_m, by_z) - begin);
  const int last = static_cast<int>(std::lower_bound(begin, end, z + range_m, by_z) - begin);
  return {first, last};
}
constexpr double kParkedExistenceRangeM = 80.0;  // well beyond any sensor range of the city

// A car that exists during frames [first_frame, last_frame) of the sequence, driven by `command`.
SimObject CityCar(int id, const GroundPose& start, const std::function<SpeedCommand(double)>& command, int first_frame,
                  int last_frame) {
  SimObject car;
  car.object_id = id;
  car.category = "VEHICLE";
  const double l = 4.2, w = 1.8, h = 1.5;
  car.surface = SampleBox(l, w, h, 0.45);
  car.centroid_body = Vec3(0.0, -h / 2.0, 0.0);
  car.box_lwh = Vec3(l, w, h);
  const auto path = IntegrateUnicycle(start, command, last_frame - first_frame, kFps);
  for (int k = first_frame; k < last_frame; ++k)
    car.L_world_object[k] = VehiclePoseOnGround(path[k - first_frame], kGroundY);
  return car;
}

// The city repeats exactly every kCityCycleFrames: the camera's weave has a period that divides the
// cycle, the static texture and the parked cars are one random pattern tiled along the road, and each
// cycle's moving cars leave the view before the cycle ends. Frame k and frame k + n * cycle therefore
// see the same scene, which makes the sliding window's cost comparable along a long run.
SimWorld CityWorld(int frames, uint64_t seed) {
  SimWorld world;
  world.name = "city";
  world.frame_rate_hz = kFps;
  const double cycle_s = kCityCycleFrames / kFps;
  const double weave_period_s = cycle_s / 3.0;
  const auto camera_path = IntegrateUnicycle(
      GroundPose{},
      [weave_period_s](double t) { return SpeedCommand{6.0, 0.04 * std::cos(2.0 * M_PI * t / weave_period_s)}; },
      frames + kCityCycleFrames, kFps);
  for (int k = 0; k < frames; ++k) world.T_world_camera.push_back(CameraPoseOnGround(camera_path[k]));
  const double cycle_advance_m = camera_path[kCityCycleFrames].z - camera_path[0].z;

  // One cycle's pattern of static points and parked cars, in road coordinates relative to the cycle start.
  std::mt19937_64 rng(seed * 7919 + 17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> pattern;
  // Sparse static texture (a busy street: much of the view is vehicles): about 50 landmarks a frame.
  for (double z = 0.0; z < cycle_advance_m; z += 1.2) {
    for (double side : {-1.0, 1.0})  // facades
      pattern.emplace_back(side * (11.5 + u(rng)), -6.0 + 7.6 * u(rng), z + 1.2 * u(rng));
    pattern.emplace_back(-8.0 + 16.0 * u(rng), kGroundY, z + 1.2 * u(rng));  // road
  }
  for (double z = 5.0; z < cycle_advance_m; z += 30.0)  // poles
    for (double side : {-1.0, 1.0})
      for (double y = kGroundY; y > -5.0; y -= 0.6) pattern.emplace_back(side * 8.0, y, z);
  std::vector<GroundPose> parked;
  for (double z = 14.0; z < cycle_advance_m + 14.0; z += 13.0 + 6.0 * u(rng))
    for (double side : {-1.0, 1.0}) parked.push_back({side * 9.3, z + 3.0 * u(rng), 0.0});

  const int cycles = (frames + kCityCycleFrames - 1) / kCityCycleFrames;
  int parked_id = kCityParkedIdBase;
  for (int tile = -1; tile <= cycles; ++tile) {  // one tile behind the start, one past the end
    const double dz = tile * cycle_advance_m;
    for (const Vec3& p : pattern) world.static_points_world.emplace_back(p.x(), p.y(), p.z() + dz);
    // Parked cars: segmented as objects, static all along. Static-only SLAM discards them. Each exists
    // only while the camera is near (a car farther than the sensor's object range is never seen), so
    // the world grows with the sequence, not with its square.
    for (const GroundPose& g : parked) {
      const double z = g.z + dz;
      const auto [first, last] = FramesNear(camera_path, frames, z, kParkedExistenceRangeM);
      if (first < last)
        world.objects.push_back(CityCar(parked_id, {g.x, z, 0.0}, [](double) { return SpeedCommand{}; }, first, last));
      ++parked_id;
    }
  }

  for (int cycle = 0; cycle < cycles; ++cycle) {
    const int k0 = cycle * kCityCycleFrames;
    const int k1 = std::min(frames, k0 + kCityCycleFrames);
    const double z0 = camera_path[k0].z;
    const int base = 10 * cycle;
    world.objects.push_back(CityCar(base + kCityAccelerating, {0.0, z0 + 10.0, 0.0},
                                    [](double t) { return SpeedCommand{Ramp(t, 0.0, 5.0, 0.6, 12.0), 0.0}; }, k0, k1));
    world.objects.push_back(CityCar(base + kCityBraking, {3.5, z0 + 20.0, 0.0},
                                    [](double t) { return SpeedCommand{Ramp(t, 1.0, 9.0, -1.5, 3.0), 0.0}; }, k0, k1));
    world.objects.push_back(CityCar(base + kCityTurning, {-3.5, z0 + 12.0, 0.0},
                                    [](double t) {
                                      const bool turning = t >= 3.0 && t < 3.0 + (M_PI / 2.0) / 0.5;
                                      return SpeedCommand{7.0, turning ? -0.5 : 0.0};
                                    },
                                    k0, k1));
    world.objects.push_back(CityCar(base + kCityStopping, {-7.0, z0 + 8.0, 0.0},
                                    [](double t) { return SpeedCommand{Ramp(t, 2.0, 12.0, -3.0, 0.0), 0.0}; }, k0, k1));
    // Hidden by traffic for a while, then it speeds away and is out of range before the cycle ends.
    SimObject hidden = CityCar(base + kCityOccluded, {7.0, z0 + 8.0, 0.0},
                               [](double t) { return SpeedCommand{Ramp(t, 20.0, 6.5, 1.0, 10.0), 0.0}; }, k0, k1);
    for (int k = k0 + kCityOcclusionBegin; k < std::min(frames, k0 + kCityOcclusionEnd); ++k)
      hidden.occluded_frames.insert(k);
    world.objects.push_back(std::move(hidden));
  }
  return world;
}

// A slow camera at a junction (the sensor model of docs/design.md §10): it creeps towards the crossing street,
// waits, and creeps on. Cars cross in front of it both ways at 30 to 60 km/h, 8 to 25 m away; others
// come the other way on the camera's street; cars are parked at the kerbs; one car ahead stops before
// the crossing and starts again.
SimWorld CrossingWorld(int frames, uint64_t seed) {
  SimWorld world;
  world.name = "crossing";
  world.frame_rate_hz = kFps;
  const auto camera_path = IntegrateUnicycle(
      GroundPose{}, [](double t) { return SpeedCommand{t < 4.0 ? 1.5 : t < 10.0 ? 0.0 : 1.0, 0.0}; }, frames, kFps);
  for (int k = 0; k < frames; ++k) world.T_world_camera.push_back(CameraPoseOnGround(camera_path[k]));

  // Facades along the camera's street with a gap for the crossing street (lanes at z = 22 and 26).
  std::mt19937_64 rng(seed * 7919 + 29);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  constexpr double kLaneA = 22.0, kLaneB = 26.0, kGapBegin = 19.0, kGapEnd = 29.0;
  for (double z = -10.0; z < 90.0; z += 0.8) {
    for (double side : {-1.0, 1.0})
      if (z < kGapBegin || z > kGapEnd) world.static_points_world.emplace_back(side * (11.5 + u(rng)), -6.0 + 7.6 * u(rng), z);
    world.static_points_world.emplace_back(-8.0 + 16.0 * u(rng), kGroundY, z + 0.8 * u(rng));
  }
  for (double x = -40.0; x < 40.0; x += 0.8) {  // the crossing street's road and far facade
    world.static_points_world.emplace_back(x, kGroundY, kGapBegin + (kGapEnd - kGapBegin) * u(rng));
    world.static_points_world.emplace_back(x, -6.0 + 7.6 * u(rng), kGapEnd + 2.0 + u(rng));
  }
  for (double z : {4.0, 16.0, 34.0})  // poles
    for (double side : {-1.0, 1.0})
      for (double y = kGroundY; y > -5.0; y -= 0.6) world.static_points_world.emplace_back(side * 8.0, y, z);

  const auto constant = [](double v) { return [v](double) { return SpeedCommand{v, 0.0}; }; };
  const auto frame_at = [frames](double t) { return std::min(frames, static_cast<int>(std::lround(t * kFps))); };
  const double kmh = 1.0 / 3.6;
  struct Crossing {
    double t0, x0, lane, yaw, speed_kmh;
  };
  // Both ways, 30 to 60 km/h; each exists from its start until it is well past the junction.
  const Crossing crossings[] = {{0.5, -35.0, kLaneA, M_PI / 2, 30.0},
                                {4.0, 45.0, kLaneB, -M_PI / 2, 50.0},
                                {11.0, -55.0, kLaneA, M_PI / 2, 60.0},
                                {15.0, 40.0, kLaneB, -M_PI / 2, 40.0}};
  int id = kCrossingFirstCrossingId;
  for (const Crossing& c : crossings) {
    const double duration = 2.0 * std::abs(c.x0) / (c.speed_kmh * kmh);
    const int first = frame_at(c.t0), last = frame_at(c.t0 + duration);
    if (first < last)
      world.objects.push_back(CityCar(id, {c.x0, c.lane, c.yaw}, constant(c.speed_kmh * kmh), first, last));
    ++id;
  }
  // Oncoming on the left lane of the camera's street.
  const std::pair<double, double> oncoming[] = {{1.0, 40.0}, {12.0, 35.0}};  // start time, km/h
  id = kCrossingFirstOncomingId;
  for (const auto& [t0, speed_kmh] : oncoming) {
    const int first = frame_at(t0), last = frame_at(t0 + 90.0 / (speed_kmh * kmh));
    if (first < last)
      world.objects.push_back(CityCar(id, {-3.5, 75.0, M_PI}, constant(speed_kmh * kmh), first, last));
    ++id;
  }
  // Ahead in the right lane: 4 m/s, brakes to a stop before the crossing at 3 s, waits until 9 s
  // while the cars cross, then pulls away at 1.5 m/s^2 up to 6 m/s.
  world.objects.push_back(CityCar(kCrossingStopAndGoId, {3.0, 12.0, 0.0},
                                  [](double t) {
                                    const double v = t < 2.0 ? 4.0 : t < 3.0 ? 4.0 - 4.0 * (t - 2.0)
                                                   : t < 9.0 ? 0.0 : std::min(6.0, 1.5 * (t - 9.0));
                                    return SpeedCommand{v, 0.0};
                                  },
                                  0, frames));
  // Parked at both kerbs, short of the junction.
  id = kCrossingParkedIdBase;
  for (const auto& [x, z] : std::vector<std::pair<double, double>>{{9.3, 6.0}, {9.3, 13.0}, {-9.3, 3.0}, {-9.3, 11.0}})
    world.objects.push_back(CityCar(id++, {x, z, 0.0}, [](double) { return SpeedCommand{}; }, 0, frames));
  return world;
}
}  // namespace

std::vector<std::string> ScenarioNames() { return {"paper", "city", "crossing"}; }

std::string ScenarioDefaultMotionMode(const std::string& name) { return name == "paper" ? "constant" : "smoothed"; }

SensorSimulator MakeScenarioSimulator(const std::string& name, const ScenarioOptions& options) {
  if (options.num_frames < 0) throw std::invalid_argument("number of frames must be >= 0");
  // The world (every object's pose in every frame it exists) is built before the first frame.
  if (options.num_frames > kMaxScenarioFrames)
    throw std::invalid_argument("number of frames must be at most " + std::to_string(kMaxScenarioFrames));
  SensorModel sensor;
  if (name == "paper")
    return SensorSimulator(PaperWorld(options.num_frames > 0 ? options.num_frames : 100), sensor, options.noise,
                           options.seed);
  if (name == "city") {
    sensor.object_max_range_m = 30.0;  // long enough to watch the stopping car park
    return SensorSimulator(CityWorld(options.num_frames > 0 ? options.num_frames : 200, options.seed), sensor,
                           options.noise, options.seed);
  }
  if (name == "crossing") {
    sensor.object_max_range_m = 30.0;  // the crossing cars are seen before they reach the camera's street
    return SensorSimulator(CrossingWorld(options.num_frames > 0 ? options.num_frames : 200, options.seed), sensor,
                           options.noise, options.seed);
  }
  throw std::invalid_argument("unknown scenario '" + name + "' (expected paper, city or crossing)");
}

Sequence MakeScenario(const std::string& name, const ScenarioOptions& options) {
  return MakeScenarioSimulator(name, options).drain();
}

}  // namespace dslam
