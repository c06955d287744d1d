#pragma once

#include <ostream>
#include <string>

#include "app/run_setup.h"

namespace dslam {

struct SimCommandOptions : CommonRunOptions {
  SimCommandOptions() { out_dir = "results/sim"; }
  std::string scenario = "paper";
  int frames = 0;  // 0: scenario default
};

// `dslam sim`: simulate, run all methods, write the result files and print the table.
// Returns the process exit code; errors are reported on `err` (never thrown).
int RunSimCommand(const SimCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace dslam
