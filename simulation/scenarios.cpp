#include "simulation/scenarios.h"

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

SimObject CityCar(int id, const GroundPose& start, const std::function<SpeedCommand(double)>& command, int cycle_start,
                  int frames) {
  SimObject car;
  car.object_id = id;
  car.category = "VEHICLE";
  const double l = 4.2, w = 1.8, h = 1.5;
  car.surface = SampleBox(l, w, h, 0.45);
  car.centroid_body = Vec3(0.0, -h / 2.0, 0.0);
  const auto path = IntegrateUnicycle(start, command, frames - cycle_start, kFps);
  for (int k = cycle_start; k < frames; ++k) car.L_world_object[k] = VehiclePoseOnGround(path[k - cycle_start], kGroundY);
  return car;
}

SimWorld CityWorld(int frames, uint64_t seed) {
  SimWorld world;
  world.name = "city";
  world.frame_rate_hz = kFps;
  // The camera weaves gently within its lane so that it also rotates.
  const auto camera_path = IntegrateUnicycle(
      GroundPose{}, [](double t) { return SpeedCommand{6.0, 0.04 * std::cos(2.0 * M_PI * t / 8.0)}; }, frames, kFps);
  for (const auto& p : camera_path) world.T_world_camera.push_back(CameraPoseOnGround(p));

  std::mt19937_64 rng(seed * 7919 + 17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double road_end = camera_path.back().z + 60.0;
  // Sparse static texture (a busy street: much of the view is vehicles): about 50 landmarks a frame.
  for (double z = -10.0; z < road_end; z += 1.2) {
    for (double side : {-1.0, 1.0})  // facades
      world.static_points_world.emplace_back(side * (11.5 + u(rng)), -6.0 + 7.6 * u(rng), z + 1.2 * u(rng));
    world.static_points_world.emplace_back(-8.0 + 16.0 * u(rng), kGroundY, z + 1.2 * u(rng));  // road
  }
  for (double z = 5.0; z < road_end; z += 30.0)  // poles
    for (double side : {-1.0, 1.0})
      for (double y = kGroundY; y > -5.0; y -= 0.6) world.static_points_world.emplace_back(side * 8.0, y, z);

  // Parked cars on both sides: segmented as objects, static all along. Static-only SLAM discards them.
  int parked_id = kCityParkedIdBase;
  for (double z = 14.0; z < road_end; z += 13.0 + 6.0 * u(rng))
    for (double side : {-1.0, 1.0}) {
      const double zz = z + 3.0 * u(rng);
      world.objects.push_back(CityCar(parked_id++, {side * 9.3, zz, 0.0}, [](double) { return SpeedCommand{}; }, 0,
                                      frames));
    }

  for (int cycle = 0; cycle * kCityCycleFrames < frames; ++cycle) {
    const int k0 = cycle * kCityCycleFrames;
    const double z0 = camera_path[k0].z;
    const int base = 10 * cycle;
    world.objects.push_back(CityCar(base + kCityAccelerating, {0.0, z0 + 10.0, 0.0},
                                    [](double t) { return SpeedCommand{Ramp(t, 0.0, 5.0, 0.6, 12.0), 0.0}; }, k0, frames));
    world.objects.push_back(CityCar(base + kCityBraking, {3.5, z0 + 20.0, 0.0},
                                    [](double t) { return SpeedCommand{Ramp(t, 1.0, 9.0, -1.5, 3.0), 0.0}; }, k0, frames));
    world.objects.push_back(CityCar(base + kCityTurning, {-3.5, z0 + 12.0, 0.0},
                                    [](double t) {
                                      const bool turning = t >= 3.0 && t < 3.0 + (M_PI / 2.0) / 0.5;
                                      return SpeedCommand{7.0, turning ? -0.5 : 0.0};
                                    },
                                    k0, frames));
    world.objects.push_back(CityCar(base + kCityStopping, {-7.0, z0 + 8.0, 0.0},
                                    [](double t) { return SpeedCommand{Ramp(t, 2.0, 12.0, -3.0, 0.0), 0.0}; }, k0, frames));
    SimObject hidden = CityCar(base + kCityOccluded, {7.0, z0 + 8.0, 0.0},
                               [](double) { return SpeedCommand{6.5, 0.0}; }, k0, frames);
    for (int k = k0 + kCityOcclusionBegin; k < std::min(frames, k0 + kCityOcclusionEnd); ++k)
      hidden.occluded_frames.insert(k);
    world.objects.push_back(std::move(hidden));
  }
  return world;
}
}  // namespace

std::vector<std::string> ScenarioNames() { return {"paper", "city"}; }

std::string ScenarioDefaultMotionMode(const std::string& name) { return name == "paper" ? "constant" : "smoothed"; }

Sequence MakeScenario(const std::string& name, const ScenarioOptions& options) {
  if (options.num_frames < 0) throw std::invalid_argument("number of frames must be >= 0");
  SensorModel sensor;
  if (name == "paper") {
    return SimulateSensor(PaperWorld(options.num_frames > 0 ? options.num_frames : 100), sensor, options.noise,
                          options.seed);
  }
  if (name == "city") {
    sensor.object_max_range_m = 30.0;  // long enough to watch the stopping car park
    return SimulateSensor(CityWorld(options.num_frames > 0 ? options.num_frames : kCityCycleFrames, options.seed),
                          sensor, options.noise, options.seed);
  }
  throw std::invalid_argument("unknown scenario '" + name + "' (expected paper or city)");
}

}  // namespace dslam
