#pragma once

#include <ostream>
#include <string>

#include "app/run_setup.h"

namespace dslam {

struct KittiReplayCommandOptions : CommonRunOptions {
  KittiReplayCommandOptions() { out_dir = "results/kitti"; }
  std::string data_dir;
  std::string sequence;  // e.g. 0000
  std::string category = "VEHICLE";  // objects the metrics are computed over ("" = all)
};


// `dslam kitti-replay`: ground-truth replay of a KITTI tracking sequence, all methods, result files,
// the metrics table and the per-object table. Returns the exit code; errors go to `err`.
int RunKittiReplayCommand(const KittiReplayCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace dslam
