#pragma once
// What issue 13 asks of the junction (`crossing` scenario), for the simulated and the rendered runs alike:
// the stop-and-go car reported standing while stopped and moving once it pulls away, parked cars never
// reported moving.

#include <gtest/gtest.h>

#include "evaluation/evaluate_run.h"
#include "simulation/scenarios.h"

namespace dslam::test {

struct StopAndGoCounts {
  int stopped = 0, stopped_standing = 0;  // pairs stopped for the classifier's half-second window
  int going = 0, going_moving = 0;        // pairs after it pulls away, over 1 m/s for as long
};

// Counts the stop-and-go car's pairs, and checks every estimated pair of a parked car: never moving,
// under 0.1 m/s.
inline StopAndGoCounts CheckJunctionObjects(const Sequence& seq, const Estimate& est) {
  const auto& car = seq.gt.objects.at(kCrossingStopAndGoId).centroid_world;
  const auto gt_speed = [&](int k) { return (car.at(k) - car.at(k - 1)).norm() * seq.frame_rate_hz; };
  StopAndGoCounts c;
  for (const ObjectPairSample& s : BuildObjectSamples(seq, est)) {
    if (!s.estimated) continue;
    if (s.object_id >= kCrossingParkedIdBase) {
      EXPECT_FALSE(s.est_dynamic) << s.object_id << " at " << s.frame;
      EXPECT_LT(s.speed_est_mps, 0.1) << s.object_id << " at " << s.frame;
    }
    if (s.object_id != kCrossingStopAndGoId || s.frame < 5) continue;
    if (gt_speed(s.frame) == 0.0 && gt_speed(s.frame - 5) == 0.0) ++c.stopped, c.stopped_standing += !s.est_dynamic;
    if (s.frame > 60 && gt_speed(s.frame) > 1.0 && gt_speed(s.frame - 5) > 1.0) ++c.going, c.going_moving += s.est_dynamic;
  }
  return c;
}

}  // namespace dslam::test
