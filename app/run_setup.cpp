#include "app/run_setup.h"

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "app/full_binary.h"
#include "pipeline/config_yaml.h"

namespace dslam {

RunConfig BuildRunConfig(const CommonRunOptions& options, EntryPoint entry, const std::string& scenario) {
  RunConfig base = DefaultRunConfig(entry, scenario);
  if (!(options.sigma_m > 0.0)) throw std::invalid_argument("--sigma must be positive");
  base.backend.noise.point_sigma_m = options.sigma_m;
  RunConfig config = options.config_path ? LoadRunConfig(*options.config_path, base) : base;
  if (options.mode) config.backend.default_mode = ParseMotionMode(*options.mode);
  if (options.schedule) config.backend.schedule = ParseSchedule(*options.schedule);
  if (options.sigma_given) config.backend.noise.point_sigma_m = options.sigma_m;
  config.validate();
  return config;
}

void RequireWritableOutDir(const std::string& dir) {
  if (dir.empty()) throw std::invalid_argument("--out must name a folder");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create the output folder " + dir + ": " + ec.message());
  const std::string probe = dir + "/.dslam_write_check";
  {
    std::ofstream out(probe, std::ios::trunc);
    out << "x";
    out.flush();
    if (!out) throw std::runtime_error("cannot write in the output folder " + dir);
  }
  std::filesystem::remove(probe, ec);
}

int DrawRunFigures(const CommonRunOptions& options, std::ostream& out, std::ostream& err) {
  if (options.no_figures) return 0;
  std::ostringstream scale;
  scale << std::setprecision(17) << options.figure_scale;
  return RunFullBinary({"figures", options.out_dir, "--scale", scale.str(), "--for-parent"}, out, err);
}

nlohmann::json RunInfo(const std::string& command, const CommonRunOptions& options, const RunConfig& config) {
  nlohmann::json info;
  info["command"] = command;
  info["seed"] = options.seed;
  info["sigma_m"] = options.sigma_m;
  info["mode"] = ToString(config.backend.default_mode);
  info["schedule"] = ToString(config.backend.schedule);
  info["config"] = options.config_path.value_or("");
  return info;
}

}  // namespace dslam
