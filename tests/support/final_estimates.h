#pragma once
// What the marginalisation tests share: a sink that records what became final.

#include <vector>

#include "backend/estimate.h"

namespace dslam::test {

struct FinalEstimates : EstimateSink {
  void cameraFinal(int frame, const SE3&) override { cameras.push_back(frame); }
  void motionFinal(const ObjectMotionEstimate& m) override { motions.push_back(m); }
  void pointFinal(const PointEstimate& p) override { points.push_back(p); }
  std::vector<int> cameras;
  std::vector<ObjectMotionEstimate> motions;
  std::vector<PointEstimate> points;
};

}  // namespace dslam::test
