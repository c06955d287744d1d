#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "app/run_setup.h"

namespace dslam {

struct RunCommandOptions : CommonRunOptions {
  RunCommandOptions() {
    out_dir = "results/run";
  }
  std::string dataset_dir;
  std::string sequence;                 // KITTI tracking layout: which sequence
  std::optional<std::string> flow;      // overrides frontend.flow_method
  int frames = 0;                       // 0: all
  std::string category = "VEHICLE";     // objects the metrics cover ("" = all)
  std::vector<std::string> methods = {"ours", "static_only", "slam_mot"};
};


// `dslam run`: the image front-end over a recorded or rendered sequence, then ours, static-only and
// SLAM+MOT; result files, metrics when the dataset has ground truth, figures. Exit codes: 0 done,
// 2 bad input or configuration, 3 figures impossible (no display).
int RunRunCommand(const RunCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace dslam
