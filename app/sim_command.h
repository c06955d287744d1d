#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

namespace dslam {

struct SimCommandOptions {
  std::string scenario = "paper";
  uint64_t seed = 1;
  std::optional<std::string> mode;      // default: the scenario's own
  std::optional<std::string> schedule;  // default: the configuration's (batch)
  std::optional<std::string> config_path;
  double sigma_m = 0.02;
  int frames = 0;  // 0: scenario default
  std::string out_dir = "results/sim";
  bool quiet = false;
};

// `dslam sim`: simulate, run all methods, write the result files and print the table.
// Returns the process exit code; errors are reported on `err` (never thrown).
int RunSimCommand(const SimCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace dslam
