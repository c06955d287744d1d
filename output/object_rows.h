#pragma once
// One row of object_motions.csv and of object_speeds.csv (headers in output/text_format.h), for every
// writer: the estimate's columns blank without an estimate, the ground truth's blank without one.

#include <ostream>

#include "backend/estimate.h"
#include "evaluation/metrics.h"

namespace dslam {

void PutObjectRows(std::ostream& motions, std::ostream& speeds, int object_id, int frame,
                   const ObjectMotionEstimate* estimate, const ObjectPairSample* ground_truth);

}  // namespace dslam
