#pragma once
// Evaluates one method's estimate of a sequence against the sequence's ground truth.

#include <optional>
#include <vector>

#include "backend/estimate.h"
#include "data/sequence.h"
#include "evaluation/metrics.h"

namespace dslam {

struct MethodMetrics {
  CameraMetrics camera;
  std::optional<double> rse_pct;
  std::optional<ObjectMetrics> objects;  // absent for a method that estimates no object motion
};

// One sample per ground-truth object frame pair (object observed by the sensor at k-1 and k).
std::vector<ObjectPairSample> BuildObjectSamples(const Sequence& seq, const Estimate& est);

MethodMetrics EvaluateEstimate(const Sequence& seq, const Estimate& est, bool estimates_objects);

}  // namespace dslam
