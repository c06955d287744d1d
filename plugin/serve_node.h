#pragma once
// `dslam serve`'s participant: per vehicle (topic namespace) it reads colour, depth, instance mask and
// odometry, assembles frames by stamp, runs the online pipeline on a worker thread and publishes the
// camera pose (nav_msgs/Odometry), the object motions and a status after every frame. No Fast DDS type
// appears in this header: the command line links it without including Fast DDS.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "geometry/pinhole_camera.h"
#include "pipeline/run_config.h"
#include "pipeline/stage_latency.h"
#include "plugin/frame_assembler.h"

namespace dslam {

struct ServeOptions {
  int domain_id = 0;
  std::string profiles_file = "config/dds_profiles.xml";
  std::vector<std::string> vehicles = {""};  // "" = no namespace (rt/camera/...)
  AssemblerParams assembler;  // its nominal_period_ns is set from frame_rate_hz
  PinholeCamera camera;          // intrinsics; width/height 0 = from the first frame
  double frame_rate_hz = 10.0;  // the sensor's: a step over 1.5 periods is a gap, n periods count n - 1 missing
  std::string out_dir = "results/serve";  // results per vehicle under out_dir/<vehicle or "default">
  // When serve falls behind: false, the newest frame wins (a frame waits at most for the one before it;
  // older waiting frames are dropped, counted, their odometry carried on), so that estimates never lag;
  // true, every assembled frame is estimated however late (a replay, an offline recording).
  bool every_frame = false;
  // The LiDAR's pose in the camera ([R | t], metric), for masks made from the LiDAR (masks.source:
  // lidar_clusters): the scans on rt/<vehicle>/lidar/points come in the LiDAR's frame.
  std::optional<Eigen::Matrix<double, 3, 4>> T_camera_lidar;
  // ROS 2 graph presence: per vehicle a node <node_name> in namespace /<vehicle> (or /), announced on
  // ros_discovery_info in the GID layout of this distribution (plugin/ros_graph.h).
  std::string node_name = "dslam";
  std::string ros_distro = "jazzy";
  // A hot standby: with a profile whose estimate_writer ownership is EXCLUSIVE, subscribers see only the
  // estimates of the live serve with the highest strength (docs/serve.md, "Hot standby"). Unset: the profile's.
  std::optional<uint32_t> ownership_strength;
};

struct VehicleStatus {
  AssemblerCounters counters;
  uint64_t frames_processed = 0;
  double last_latency_ms = 0.0;  // frame assembled -> its estimate published
  std::vector<StageLatencySummary> latency;  // per stage over the session (pipeline/stage_latency.h)
  // Another serve publishes this vehicle's estimates where subscribers would take both (shared ownership,
  // or exclusive with the same strength), and its participant's GUID is the lower: this one goes on
  // estimating and writing its results but publishes nothing until that one leaves (plugin/fleet_share.h).
  bool quiet = false;
  std::string quiet_for;  // the other participant's GUID prefix, while quiet
  uint64_t frames_not_published = 0;  // estimated while quiet
  int estimate_readers = 0;  // readers matched by the camera estimates' writer (ServeNode::status() only)
};

class ServeNode {
 public:
  // Throws std::runtime_error when the participant or an endpoint cannot be created.
  ServeNode(const ServeOptions& options, const RunConfig& config);
  ~ServeNode();
  ServeNode(const ServeNode&) = delete;
  ServeNode& operator=(const ServeNode&) = delete;

  std::map<std::string, VehicleStatus> status() const;
  // Thread-safe, also during shutdown(): the frames still waiting are dropped instead of processed, so
  // that shutdown() returns as soon as the frames in progress are done (their estimates are written).
  void abandonBacklogs();
  // Stops reading, finishes the frames already assembled, writes every vehicle's results
  // (WriteRunOutputs layout, ours, plus camera_ours_online.tum) and reports where.
  void shutdown(std::ostream& log);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dslam
