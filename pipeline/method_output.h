#pragma once
// What a streamed run does with one method's final estimates: its result files (output/streaming_sink.h)
// and, where there is ground truth, its evaluation (evaluation/streaming_evaluator.h), fed the same
// estimates as they become final. Used by every streamed run (`sim`, `kitti-replay`, `run`).

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "backend/methods.h"
#include "evaluation/streaming_evaluator.h"
#include "output/run_report.h"
#include "output/streaming_sink.h"

namespace dslam {

// The files of a method in the layout WriteRunOutputs writes (camera_<method>.{tum,kitti}; ours' online
// poses, object tables and map points; SLAM+MOT's object tables with suffix _slam_mot).
StreamedFiles FilesOf(Method method);

class MethodOutput : public EstimateSink {
 public:
  // `dir` empty: no files. `gt` null: no evaluation (metrics() is empty); else it must outlive this and
  // know each frame's observed objects before frameMade() of that frame.
  MethodOutput(Method method, const std::string& dir, const GroundTruth* gt, double frame_rate_hz,
               const std::string& category);

  // Frame k reached the methods (in order), with its stamp.
  void frameMade(int frame, int64_t t_ns);
  // Ours' pose right after frame `t_ns` was added.
  void onlinePose(int64_t t_ns, const SE3& T_world_camera);

  void cameraFinal(int frame, const SE3& T_world_camera) override;
  void motionFinal(const ObjectMotionEstimate& motion) override;
  void pointFinal(const PointEstimate& point) override;
  void cameraStepCovariance(int frame, const Mat6& covariance) override;

  // After the method's last estimate: completes the files.
  void finish();
  MethodMetrics metrics() const;                // empty without ground truth
  std::vector<ObjectSummary> objects() const;   // per ground-truth object; empty without ground truth

 private:
  std::optional<StreamingEvaluator> evaluator_;
  std::optional<StreamingFileSink> files_;
};

// One output per method named (a method named twice gets one), as MethodOutput's arguments say.
using MethodOutputs = std::map<Method, std::unique_ptr<MethodOutput>>;
MethodOutputs MakeMethodOutputs(const std::vector<Method>& methods, const std::string& dir, const GroundTruth* gt,
                                double frame_rate_hz, const std::string& category);

// After the methods' last estimates: completes every output's files and returns each method's metrics
// with its estimators' time (`wall_time_s(method)`); `ours_objects` receives ours' per-object summary.
MethodOutcomes FinishMethodOutputs(MethodOutputs& outputs, const std::function<double(Method)>& wall_time_s,
                                   std::vector<ObjectSummary>* ours_objects);

}  // namespace dslam
