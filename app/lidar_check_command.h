#pragma once

#include <ostream>
#include <string>

namespace dslam {

struct LidarCheckCommandOptions {
  std::string dataset_dir;  // a recording with LiDAR scans (kitti-raw layout with velodyne_points/)
  std::string run_dir;      // a `dslam run` result folder on it (optional: the reference alone without it)
  std::string config_path;  // the run's configuration: its lidar_masks keys shape the clusters too
  std::string out_dir = "results/lidar_check";
  int frames = 0;           // 0: all
  bool quiet = false;
};

// `dslam lidar-check`: the LiDAR-only reference of a recording (lidar_ego.tum, lidar_tracks.csv) and, with
// --run, that run checked against it (lidar_check.json and a table).
// Exit codes: 0 done, 2 bad input (unreadable dataset or results, no LiDAR scans, unwritable folder).
int RunLidarCheckCommand(const LidarCheckCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace dslam
