#pragma once
// Evaluates one method's estimate of a sequence against the sequence's ground truth.

#include <map>
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

// The ground-truth sample of object `object_id` over frame - 1 -> frame, without estimate; nullopt unless
// the sensor observed the object in both frames.
std::optional<ObjectPairSample> GroundTruthPair(const GroundTruth& gt, double frame_rate_hz, int object_id, int frame);

// The run's id of ground-truth object `gt_id` over frame - 1 -> frame (GroundTruth::run_object_ids): its own id
// when the run's ids are the ground truth's; else the id the run gave it in both frames, or 0 (no estimate of
// it) when the run had it in one of them only, or under two ids (its track restarted, or it took another's).
int RunObjectId(const GroundTruth& gt, int gt_id, int frame);
// The inverse: the ground-truth object the run's object `run_id` is over frame - 1 -> frame (RunObjectId of
// it is `run_id`), or nullopt when none is.
std::optional<int> GroundTruthIdOf(const GroundTruth& gt, int run_id, int frame);

// Fills the sample's estimate fields from `motion`.
void SetEstimate(const ObjectMotionEstimate& motion, ObjectPairSample* sample);

// One sample per ground-truth object frame pair (object observed by the sensor at k-1 and k), for
// objects of `category` only when it is not empty (e.g. "VEHICLE").
std::vector<ObjectPairSample> BuildObjectSamples(const Sequence& seq, const Estimate& est,
                                                 const std::string& category = "");

MethodMetrics EvaluateEstimate(const Sequence& seq, const Estimate& est, bool estimates_objects,
                               const std::string& category = "");

// Per-object results of a run (objects.csv, the console's object table).
struct ObjectSummary {
  int object_id = 0;
  std::string category;
  int gt_pairs = 0;
  int frames_estimated = 0;
  ObjectMetrics metrics;
  std::optional<double> mean_gt_speed_kmh;   // over estimated frame pairs
  std::optional<double> mean_est_speed_kmh;
};

// The summaries accumulated sample by sample, in any order.
class ObjectSummaries {
 public:
  void add(const ObjectPairSample& sample, const std::string& category);
  // In two steps, as ObjectMetricsAccumulator.
  void addPair(const ObjectPairSample& pair, const std::string& category);
  void addEstimate(const ObjectPairSample& sample);
  // One summary per object with a sample, by id.
  std::vector<ObjectSummary> result() const;

 private:
  struct PerObject {
    std::string category;
    ObjectMetricsAccumulator metrics;
    double sum_gt_mps = 0.0, sum_est_mps = 0.0;
  };
  std::map<int, PerObject> objects_;
};

// One summary per ground-truth object that was observed in two consecutive frames at least.
std::vector<ObjectSummary> SummariseObjects(const Sequence& seq, const Estimate& est);

}  // namespace dslam
