#pragma once
// What every run command shares: the run configuration from --config and the command-line
// overrides, and the writing of results with the console tables.

#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "output/run_report.h"
#include "pipeline/run_config.h"
#include "pipeline/run_defaults.h"

namespace dslam {

struct CommonRunOptions {
  std::optional<std::string> config_path;
  std::optional<std::string> mode;      // overrides the configuration's motion model
  std::optional<std::string> schedule;  // overrides the configuration's schedule
  double sigma_m = 0.02;                // point noise: simulated and assumed by the back-end
  bool sigma_given = true;              // --sigma was typed (else the file's point_sigma_m wins over it)
  uint64_t seed = 1;
  std::string out_dir;
  bool quiet = false;
  bool no_figures = false;    // skip the figures drawn at the end of the run
  double figure_scale = 1.0;  // FigureOptions::scale of those figures
};

// Settings in this order, each over the previous: built-in defaults; the entry point's defaults
// (pipeline/run_defaults.h; `scenario`: sim's) and sigma_m; the configuration file; the flags the user typed
// (--mode, --schedule, --sigma when sigma_given).
// Throws std::invalid_argument with a message naming the bad option.
RunConfig BuildRunConfig(const CommonRunOptions& options, EntryPoint entry, const std::string& scenario = "");

// Creates --out and checks that files can be written in it, before any computation: an unwritable
// folder found only at the end loses the whole run. Throws std::runtime_error naming the folder.
void RequireWritableOutDir(const std::string& dir);

// The figures at the end of a run (unless options.no_figures), drawn by `dslam-full figures` as a child
// (app/full_binary.h): its exit code.
int DrawRunFigures(const CommonRunOptions& options, std::ostream& out, std::ostream& err);

// Fills the parameters every run records in metrics.json's "run" object.
nlohmann::json RunInfo(const std::string& command, const CommonRunOptions& options, const RunConfig& config);

}  // namespace dslam
