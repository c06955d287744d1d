#pragma once
// Built-in simulated scenarios (docs/design.md §10):
//  - "paper": the simulated experiment of Henein et al. 2020: one ellipsoid-shaped rigid object with a
//    constant SE(3) pose change, a camera on a circular path that keeps it in view, no static structure.
//  - "city": a street with sparse static landmarks (facades, ground, poles), parked cars on both sides
//    and, every 200 frames, five moving cars: accelerating, braking, turning off, stopping (then
//    parked) and one hidden for 15 frames. The scene repeats exactly every 300 frames.
//  - "crossing": a slow camera at a junction (creeping, waiting from 4 to 10 s, creeping on): cars
//    crossing in front both ways at 30 to 60 km/h 8 to 25 m away, oncoming cars, parked cars at both
//    kerbs, and a car ahead that stops before the crossing (3 to 9 s) and starts again.

#include <cstdint>
#include <string>
#include <vector>

#include "data/sequence.h"
#include "simulation/sensor_simulator.h"

namespace dslam {

constexpr int kMaxScenarioFrames = 100000;

struct ScenarioOptions {
  int num_frames = 0;  // 0: the scenario's default length
  uint64_t seed = 1;
  SimNoise noise;
};

std::vector<std::string> ScenarioNames();
// Throws std::invalid_argument for an unknown name or bad options.
// The scenario's frames one at a time (long runs).
SensorSimulator MakeScenarioSimulator(const std::string& name, const ScenarioOptions& options);
// All of them at once.
Sequence MakeScenario(const std::string& name, const ScenarioOptions& options);
// The motion model the scenario is meant for ("constant" for paper, "smoothed" for city and crossing).
std::string ScenarioDefaultMotionMode(const std::string& name);

// City object ids of cycle c (frames [300c, 300c + 300)): 10 * c + role, role 1..5.
enum CityRole { kCityAccelerating = 1, kCityBraking = 2, kCityTurning = 3, kCityStopping = 4, kCityOccluded = 5 };
constexpr int kCityCycleFrames = 300;  // the city repeats exactly with this period
constexpr int kCityParkedIdBase = 1000;  // parked cars: ids 1000, 1001, ...
// Crossing object ids: the crossing cars, the oncoming ones, the stop-and-go car, the parked ones.
constexpr int kCrossingFirstCrossingId = 1, kCrossingFirstOncomingId = 11, kCrossingStopAndGoId = 21;
constexpr int kCrossingParkedIdBase = 1000;
// Frames of a cycle during which the kCityOccluded car is hidden.
constexpr int kCityOcclusionBegin = 60, kCityOcclusionEnd = 75;

}  // namespace dslam
