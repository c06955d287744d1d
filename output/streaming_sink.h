#pragma once
// A method's result files written while the run goes, so that a crash or SIGKILL loses at most the
// frames still inside the smoother's window. Each estimate is appended as it becomes final
// (EstimateSink), and the files are flushed once per frame (when a camera becomes final, and after each
// online pose). For ours, by default:
//   camera_ours.tum          final camera poses, in frame order;
//   camera_ours_online.tum   each frame's pose as published right after that frame;
//   object_motions.csv       final object motions;
//   object_speeds.csv        final object speeds;
//   map_points.csv           final points: dynamic points once per observation, a landmark once its
//                            sighting ends (its last observation left the window), with its final value.
// Call finish() after the last estimate: it writes the landmarks still in sight. Without ground truth
// the object tables' ground-truth columns stay empty, and WriteRunOutputs replaces the files whole at
// the end of a run. With ground truth that exists from the start (the simulator's), the rows carry it and
// finish() appends a row for each ground-truth pair that got no estimate: the files are then the run's
// final ones, in the formats WriteRunOutputs writes (rows in another order).

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "output/whole_line_file.h"
#include "backend/estimate.h"
#include "data/ground_truth.h"

namespace dslam {

struct StreamedFiles {
  std::string method = "ours";  // camera_<method>.tum
  bool online = true;           // camera_<method>_online.tum
  bool kitti = false;           // camera_<method>.kitti too
  bool object_tables = true;    // object_motions<suffix>.csv and object_speeds<suffix>.csv
  std::string object_suffix;    // e.g. "_slam_mot"
  bool map_points = true;       // map_points.csv
};

class StreamingFileSink : public EstimateSink {
 public:
  // The files are created in `dir` (and earlier ones truncated) with the first estimate, so a run that
  // produced nothing leaves nothing. Every call throws std::runtime_error naming what cannot be written.
  // `gt`, when given, must outlive the sink; its observed frames must be known up to each motion's frame.
  explicit StreamingFileSink(const std::string& dir, StreamedFiles files = {}, const GroundTruth* gt = nullptr,
                             double frame_rate_hz = 10.0);

  // The stamp of a frame the estimator received (frames in order); needed before its camera is final.
  void frameStamp(int frame, int64_t t_ns);
  // The pose published right after frame `t_ns` was added.
  void onlinePose(int64_t t_ns, const SE3& T_world_camera);

  void cameraFinal(int frame, const SE3& T_world_camera) override;
  void motionFinal(const ObjectMotionEstimate& motion) override;
  void pointFinal(const PointEstimate& point) override;
  // Flushes everything received so far.
  void flush();
  // After the last estimate: writes the landmarks still in sight and, with ground truth, the ground-truth
  // pairs without estimate; flushes.
  void finish();

 private:
  void open();
  void putPoint(int frame, int object_id, const Vec3& p_world);
  void writeLandmarksSeenBefore(int frame);

  std::string dir_;
  StreamedFiles files_;
  const GroundTruth* gt_;
  double frame_rate_hz_;
  bool opened_ = false;
  std::deque<std::pair<int, int64_t>> stamps_;  // frames whose camera is not final yet
  // With ground truth: per object, which frames (from its first pose on) got an estimate; a bit each.
  std::map<int, std::vector<bool>> estimated_;
  std::unordered_map<int64_t, std::pair<int, Vec3>> landmarks_;  // in sight: last final frame, value
  // Whole rows only on disk, whatever ends the process (output/whole_line_file.h).
  WholeLineFile camera_, kitti_, online_, motions_, speeds_, points_;
};

}  // namespace dslam
