#pragma once
// Evaluates one method's estimates as they become final (an EstimateSink), against ground truth that
// exists from the start (the simulator's). It keeps sums, not estimates: what a run holds for its
// evaluation is one estimated camera pose a frame (points wait for their camera) instead of every
// point, motion and pose. Its metrics are those of EvaluateEstimate on the collected estimate (sums in
// another order: equal to rounding).

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "backend/estimate.h"
#include "data/ground_truth.h"
#include "evaluation/evaluate_run.h"

namespace dslam {

class StreamingEvaluator : public EstimateSink {
 public:
  // `gt` must outlive the evaluator. Object metrics over objects of `category` only when it is not
  // empty; the per-object summaries cover every object.
  StreamingEvaluator(const GroundTruth& gt, double frame_rate_hz, bool estimates_objects, std::string category = "");

  // Call once per frame, in order, once the ground truth knows which objects the frame saw (and, with
  // GroundTruth::run_object_ids, which run object each is): counts the object pairs that end in it.
  void frameMade(int frame);
  void frameMade(const FrameMeasurement& frame) { frameMade(frame.frame_index); }

  void cameraFinal(int frame, const SE3& T_world_camera) override;
  void motionFinal(const ObjectMotionEstimate& motion) override;
  void pointFinal(const PointEstimate& point) override;
  void cameraStepCovariance(int frame, const Mat6& covariance) override;

  // After the method's last estimate. Throws std::logic_error when a made frame has no final camera or
  // a point still waits for its camera.
  MethodMetrics metrics() const;
  std::vector<ObjectSummary> objects() const { return summaries_.result(); }

 private:
  void addPoint(const PointEstimate& point);

  const GroundTruth& gt_;
  double frame_rate_hz_;
  bool estimates_objects_;
  std::string category_;
  int frames_made_ = 0;
  std::vector<SE3> T_world_camera_est_;  // final cameras, by frame
  std::multimap<int, PointEstimate> waiting_;  // points whose camera is not final yet, by frame
  std::optional<std::pair<int, Mat6>> step_covariance_;  // of the next final camera's step, when given
  CameraMetricsAccumulator camera_;
  RseAccumulator structure_;
  ObjectMetricsAccumulator objects_;
  ObjectSummaries summaries_;
};

}  // namespace dslam
