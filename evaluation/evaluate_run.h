#pragma once
// Evaluates one method's estimate of a sequence against the sequence's ground truth.

#include <optional>
#include <string>
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

// One sample per ground-truth object frame pair (object observed by the sensor at k-1 and k), for
// objects of `category` only when it is not empty (e.g. "VEHICLE").
std::vector<ObjectPairSample> BuildObjectSamples(const Sequence& seq, const Estimate& est,
                                                 const std::string& category = "");

MethodMetrics EvaluateEstimate(const Sequence& seq, const Estimate& est, bool estimates_objects,
                               const std::string& category = "");

}  // namespace dslam
