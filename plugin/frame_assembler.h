#pragma once
// Assembles the per-frame inputs that arrive on separate topics (colour, depth, instance mask,
// odometry) into one ImageFrame, by their header stamp. Nothing here blocks or grows without bound:
//  - a set is complete when it has colour, depth, a mask (when masks are expected), a LiDAR scan (when
//    scans are expected) and odometry (when odometry is expected); complete sets are released in stamp order;
//  - a set older than `timeout_ns` behind the newest stamp seen is dropped as incomplete;
//  - when no part at all has arrived for `silence_timeout_ns` of wall time (the stream stopped, so no
//    newer stamp will come), the incomplete sets still waiting are dropped too;
//  - at most `max_pending` sets wait; a new stamp beyond that drops the oldest (counted);
//  - a part whose stamp is not newer than the last released frame is rejected (stamps going backwards);
//  - with a nominal frame period, the frames between two frames seen of which no part arrived are counted.
// Middleware-free: the DDS readers hand it decoded parts (plugin/image_message.h).

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "data/image_frame.h"

namespace dslam {

struct AssemblerParams {
  bool expect_mask = true;
  bool expect_odometry = false;
  bool expect_lidar = false;  // masks made from the LiDAR: a scan instead of a mask
  int64_t timeout_ns = 500'000'000;  // 0.5 s: five frames at 10 Hz
  // Longer than a sensor's gap between frames, so that only a stopped stream triggers it.
  int64_t silence_timeout_ns = 2'000'000'000;
  int max_pending = 8;  // 1..64
  // And at most this many bytes of pixels waiting: beyond, the oldest set is dropped and counted (a
  // count alone let large images grow the backlog to gigabytes).
  size_t max_pending_bytes = size_t{256} << 20;
  // The sensor's frame period: a step between two frames seen of n periods means n - 1 frames of which
  // no part arrived (counted as missing). 0: not counted.
  int64_t nominal_period_ns = 0;
  // Sigma of an odometry increment whose message gave no twist covariance ([m x3; rad x3]).
  Vec6 default_increment_sigma = Vec6::Constant(0.01);
  void validate() const;
};

struct AssemblerCounters {
  uint64_t parts_received = 0;
  uint64_t frames_assembled = 0;
  uint64_t dropped_incomplete = 0;
  uint64_t dropped_queue_full = 0;
  uint64_t rejected_invalid = 0;
  uint64_t samples_lost = 0;  // not the assembler's: what serve's DDS readers reported lost (SAMPLE_LOST)
  // Frames between two frames seen (assembled or dropped) of which no part arrived, by the nominal period:
  // lost whole on the way, which DDS does not always report (a keep-last writer that overwrites a sample
  // before its repair sends a GAP, which the reader takes as not relevant).
  uint64_t frames_missing = 0;
  std::string last_rejection;
};

// A LiDAR scan in the camera's frame (ImageFrame's lidar_* fields; see SetLidarScan).
struct LidarPart {
  std::vector<Eigen::Vector3f> points_camera;
  Eigen::Vector3f origin_camera = Eigen::Vector3f::Zero();
  Eigen::Vector3f up_camera = Eigen::Vector3f(0.0f, -1.0f, 0.0f);
};

// A vehicle pose at a stamp (odometry input: the pose of the vehicle's camera in its odometry frame).
struct StampedPose {
  SE3 T_odom_camera;
  // The odometry's velocity uncertainty per second ([x y z roll pitch yaw], from the message's twist
  // covariance): the increment between two released frames gets this times the time between them.
  // Absent: AssemblerParams::default_increment_sigma. (The pose covariance grows along a drive and says
  // nothing about one increment.)
  std::optional<Vec6> twist_sigma_per_s;
};

// When a part arrived (steady clock ns, SteadyClockNs; 0 = when it reaches the assembler) and how long
// decoding it took: each released frame's FrameTiming starts from its parts' (first arrival, decoding
// summed).
struct PartArrival {
  int64_t arrived_ns = 0;
  double decode_ms = 0.0;
};

// Monotonic wall time in ns; injectable so that tests control it.
using WallClockNs = std::function<int64_t()>;

class FrameAssembler {
 public:
  explicit FrameAssembler(const AssemblerParams& params, WallClockNs wall_clock_ns = SteadyClockNs);

  void addColour(int64_t t_ns, const cv::Mat& image, const PartArrival& arrival = {});
  void addDepth(int64_t t_ns, const cv::Mat& depth_m, const PartArrival& arrival = {});
  void addMask(int64_t t_ns, const cv::Mat& instance_ids, const PartArrival& arrival = {});
  void addOdometry(int64_t t_ns, const StampedPose& pose, const PartArrival& arrival = {});
  void addLidar(int64_t t_ns, LidarPart scan, const PartArrival& arrival = {});
  // Counts a sample that could not be decoded (the reason names the topic and the problem).
  void reject(const std::string& reason);

  // Complete frames in stamp order, numbered 0, 1, 2, ... with the odometry increment from the
  // previous released frame's pose, and their timing (received, decode, assembled: now). Also applies the timeouts: against the newest stamp seen, and
  // against the wall time since the last part arrived.
  std::vector<ImageFrame> takeReady();

  const AssemblerCounters& counters() const { return counters_; }

 private:
  struct Pending {
    cv::Mat colour, depth, mask;
    std::optional<StampedPose> pose;
    std::optional<LidarPart> lidar;
    FrameTiming timing;  // received_ns: the first part's arrival; decode_ms summed over the parts
  };
  Pending* slot(int64_t t_ns, const char* what, const PartArrival& arrival);
  bool complete(const Pending& p) const;
  void boundPendingBytes();
  // A set leaves (released or dropped; sets leave in stamp order): counts the frames missing before it.
  void leaving(int64_t t_ns);

  AssemblerParams params_;
  WallClockNs wall_clock_ns_;
  int64_t last_arrival_wall_ns_ = 0;
  std::map<int64_t, Pending> pending_;
  std::optional<int64_t> last_released_ns_;
  std::optional<int64_t> last_left_ns_;  // the stamp of the last set that left, released or dropped
  std::optional<StampedPose> last_released_pose_;
  int64_t last_released_pose_ns_ = 0;
  int64_t newest_ns_ = 0;
  int next_frame_index_ = 0;
  AssemblerCounters counters_;
};

}  // namespace dslam
