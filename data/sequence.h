#pragma once

#include <string>
#include <vector>

#include "data/ground_truth.h"
#include "data/measurements.h"

namespace dslam {

// A recorded or generated run: measurements in frame order, and ground truth when known.
struct Sequence {
  std::string name;
  double frame_rate_hz = 10.0;
  std::vector<FrameMeasurement> frames;
  GroundTruth gt;
};

}  // namespace dslam
