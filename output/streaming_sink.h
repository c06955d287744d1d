#pragma once
// Ours' result files written while the run goes, so that a crash or SIGKILL loses at most the frames
// still inside the smoother's window. Each estimate is appended as it becomes final (EstimateSink), and
// the files are flushed once per frame (when a camera becomes final, and after each online pose):
//   camera_ours.tum          final camera poses, in frame order;
//   camera_ours_online.tum   each frame's pose as published right after that frame;
//   object_motions.csv       final object motions (the ground-truth columns empty);
//   object_speeds.csv        final object speeds (gt_speed_mps empty);
//   map_points.csv           final points: dynamic points once per observation, a landmark at each of its
//                            observations as it leaves the window (the last row is its final estimate).
// The formats are those WriteRunOutputs writes at the end of a run, which replaces these files whole
// with the ground truth filled in and each landmark once.

#include <cstdint>
#include <deque>
#include <fstream>
#include <string>
#include <utility>

#include "backend/estimate.h"

namespace dslam {

class StreamingFileSink : public EstimateSink {
 public:
  // The files are created in `dir` (and earlier ones truncated) with the first estimate, so a run that
  // produced nothing leaves nothing. Every call throws std::runtime_error naming what cannot be written.
  explicit StreamingFileSink(const std::string& dir);

  // The stamp of a frame the estimator received (frames in order); needed before its camera is final.
  void frameStamp(int frame, int64_t t_ns);
  // The pose published right after frame `t_ns` was added.
  void onlinePose(int64_t t_ns, const SE3& T_world_camera);

  void cameraFinal(int frame, const SE3& T_world_camera) override;
  void motionFinal(const ObjectMotionEstimate& motion) override;
  void pointFinal(const PointEstimate& point) override;
  // Flushes everything received so far.
  void flush();

 private:
  void open();

  std::string dir_;
  bool opened_ = false;
  std::deque<std::pair<int, int64_t>> stamps_;  // frames whose camera is not final yet
  std::ofstream camera_, online_, motions_, speeds_, points_;
};

}  // namespace dslam
