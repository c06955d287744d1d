// Settings mean what they say: built-in defaults, then the command's defaults, then the --config file,
// then only the flags the user typed (the file's mode, schedule and sigma used to be overwritten).
#include <gtest/gtest.h>

#include <fstream>

#include "app/dds_commands.h"
#include "app/run_command.h"
#include "app/run_setup.h"
#include "pipeline/config_yaml.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

std::string ConfigFile(const std::string& name, const std::string& yaml) {
  const std::string path = test::TempPath(name);
  std::ofstream(path) << yaml;
  return path;
}

TEST(SettingsOrder, TheFileWinsOverTheCommandsDefaultsAndTypedFlagsWinOverTheFile) {
  const std::string file = ConfigFile("order.yaml",
                                      "backend:\n  motion_mode: constant\n  schedule: window:6\nnoise:\n"
                                      "  point_sigma_m: 0.05\n");
  RunCommandOptions run;  // dslam run: smoothed, window:10, sigma 0.02 by default
  run.config_path = file;
  run.sigma_given = false;
  RunConfig c = BuildRunConfig(run, EntryPoint::kRun);
  EXPECT_EQ(c.backend.default_mode, MotionMode::kConstant);
  EXPECT_EQ(ToString(c.backend.schedule), "window:6");
  EXPECT_DOUBLE_EQ(c.backend.noise.point_sigma_m, 0.05);

  run.mode = "per-step";
  run.schedule = "batch";
  run.sigma_m = 0.03, run.sigma_given = true;
  c = BuildRunConfig(run, EntryPoint::kRun);
  EXPECT_EQ(c.backend.default_mode, MotionMode::kPerStep);
  EXPECT_EQ(ToString(c.backend.schedule), "batch");
  EXPECT_DOUBLE_EQ(c.backend.noise.point_sigma_m, 0.03);

  // A file that sets none of them leaves the command's defaults.
  run = RunCommandOptions();
  run.config_path = ConfigFile("other.yaml", "classifier:\n  min_static_inliers: 12\n");
  run.sigma_given = false;
  c = BuildRunConfig(run, EntryPoint::kRun);
  EXPECT_EQ(c.backend.default_mode, MotionMode::kSmoothed);
  EXPECT_EQ(ToString(c.backend.schedule), "window:10");
  EXPECT_DOUBLE_EQ(c.backend.noise.point_sigma_m, 0.02);
  EXPECT_EQ(c.classifier.min_static_inliers, 12);
}

TEST(SettingsOrder, ServeTakesTheFilesModeAndScheduleOverItsDefaults) {
  ServeCommandOptions serve;
  EXPECT_EQ(ServeRunConfig(serve).backend.default_mode, MotionMode::kSmoothed);
  EXPECT_EQ(ToString(ServeRunConfig(serve).backend.schedule), "window:10");
  serve.config_path = ConfigFile("serve.yaml", "backend:\n  motion_mode: per-step\n  schedule: window:4\n");
  const RunConfig c = ServeRunConfig(serve);
  EXPECT_EQ(c.backend.default_mode, MotionMode::kPerStep);
  EXPECT_EQ(ToString(c.backend.schedule), "window:4");
}

TEST(SettingsOrder, ASectionOrKeyGivenTwiceIsAnError) {
  try {
    ParseRunConfig("backend:\n  schedule: batch\nbackend:\n  schedule: window:5\n", "twice.yaml");
    FAIL() << "a repeated section was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("section 'backend' appears twice"), std::string::npos) << e.what();
  }
  try {
    ParseRunConfig("noise:\n  point_sigma_m: 0.1\n  point_sigma_m: 0.2\n", "twice.yaml");
    FAIL() << "a repeated key was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'noise.point_sigma_m' appears twice"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dslam
