#pragma once
// A recording of n frames replayed forwards and backwards in turn as one continuous drive (0 .. n-1, then
// n-2 .. 1, then 0 .. again): long runs from a short recording, for memory benchmarks. Step i of the drive
// is recorded frame PingPongFrame(i, n), numbered i and stamped i periods after step 0; its odometry is the
// recorded increment forwards and the inverse of the one it undoes backwards.

#include <cstdint>
#include <functional>
#include <optional>

#include "data/image_frame.h"

namespace dslam {

// The recorded frame (0 .. n-1) at step i >= 0 of the drive; n >= 2.
int PingPongFrame(int i, int n);

// Turns `recorded` (frame PingPongFrame(i, n)) into step i of the drive. `odometry_into(k)`: the recorded
// increment into frame k (none for frame 0 or without odometry). Dense flow to the next frame is kept only
// where the next step is the next recorded frame.
void ToPingPongStep(int i, int n, int64_t period_ns,
                    const std::function<std::optional<OdometryMeasurement>(int)>& odometry_into, ImageFrame* recorded);

}  // namespace dslam
