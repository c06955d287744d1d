#pragma once
// `dslam serve`, `dslam publish` and `dslam listen`: the DDS participant, the dataset replayer and a
// subscriber of the estimates (plugin/).

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "plugin/dataset_publisher.h"
#include "plugin/serve_node.h"

namespace dslam {

struct ServeCommandOptions {
  std::optional<std::string> config_path;
  std::string calib_path;               // KITTI-format calib.txt: the camera's intrinsics (P2, else P0)
  std::vector<std::string> vehicles;    // empty: one pipeline without namespace
  std::string fleet_share;              // "K/N": serve only this host's share of the vehicles (fleet_share.h)
  int domain_id = 0;
  std::string profiles_file = DSLAM_DEFAULT_DDS_PROFILES;
  std::string out_dir = "results/serve";
  bool no_odometry = false;             // do not wait for odometry with every frame
  double frame_rate_hz = 10.0;
  int timeout_ms = 500;                 // an incomplete set this far behind the newest stamp is dropped
  int silence_ms = 2000;                // with no sample for this long, incomplete sets are dropped
  int max_pending = 8;                  // frame sets waiting for assembly or for the pipeline (oldest dropped)
  int max_pending_mb = 256;             // ... and at most this many MiB of their pixels
  bool every_frame = false;             // estimate every frame however late (else the newest frame wins)
  double status_every_s = 5.0;          // status line period on the console (0: never)
  double max_run_s = 0.0;               // stop by itself after this long (0: only on SIGINT/SIGTERM)
  std::string node_name = "dslam";      // ROS 2 node per vehicle, for `ros2 node list`
  std::string ros_distro = "jazzy";     // the graph topic's GID layout
  int ownership_strength = -1;          // a hot standby's strength (EXCLUSIVE ownership); -1: the profile's
};

// Runs until SIGINT or SIGTERM (or max_run_s), then writes every vehicle's results. Exit codes: 0 done,
// 2 bad options or configuration, 4 DDS could not start.
// serve's run configuration: its defaults (pipeline/run_defaults.h), then the --config file over them.
RunConfig ServeRunConfig(const ServeCommandOptions& options);

int RunServeCommand(const ServeCommandOptions& options, std::ostream& out, std::ostream& err);

struct PublishCommandOptions {
  PublishCommandOptions() { publish.profiles_file = DSLAM_DEFAULT_DDS_PROFILES; }
  std::string dataset_dir;
  std::string sequence;
  // The run configuration whose `dataset:` section reads the dataset (depth encoding, LiDAR fill radius,
  // frame rate), so that what is published is what `dslam run` reads with the same file.
  std::optional<std::string> config_path;
  std::string compress = "none";  // none, png or jpeg (plugin/compressed_image.h)
  PublishOptions publish;
};

int RunPublishCommand(const PublishCommandOptions& options, std::ostream& out, std::ostream& err);

// A subscriber host's view of a vehicle's estimates: every camera estimate received, streamed to
// OUT/estimates.csv, with which writer sent it and the latency from its capture stamp; at the end the
// totals in OUT/listen.json (repeated or missing frames, the longest silence, the latency).
struct ListenCommandOptions {
  std::string vehicle;
  int domain_id = 0;
  std::string profiles_file = DSLAM_DEFAULT_DDS_PROFILES;
  std::string out_dir = "results/listen";
  double frame_rate_hz = 10.0;   // the sensor's rate: frames missing between stamps are counted at it
  int frames = 0;                // stop after this many frames (distinct stamps; 0: no limit)
  double max_run_s = 0.0;        // stop after this long (0: never)
  double idle_stop_s = 0.0;      // stop when nothing arrived for this long since the last estimate (0: never)
  double status_every_s = 5.0;   // console status period (0: never)
};

// Exit codes: 0 done, 2 bad options, 4 DDS could not start or the output cannot be written.
int RunListenCommand(const ListenCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace dslam
