#include "app/sim_command.h"

#include <gtest/gtest.h>

#include "support/temp_paths.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace dslam {
namespace {

using test::TempPath;


void ExpectFailure(SimCommandOptions options, const std::string& fragment) {
  std::ostringstream out, err;
  EXPECT_EQ(RunSimCommand(options, out, err), 2);
  EXPECT_NE(err.str().find(fragment), std::string::npos) << err.str();
}

TEST(SimCommand, BadConfigurationIsAClearError) {
  SimCommandOptions o;
  o.out_dir = TempPath("bad");
  o.frames = 5;
  o.sigma_m = -0.02;
  ExpectFailure(o, "--sigma must be positive");
  o.sigma_m = 0.02;
  o.mode = "wobbly";
  ExpectFailure(o, "unknown motion mode 'wobbly'");
  o.mode.reset();
  o.schedule = "window:1";
  ExpectFailure(o, "W must be at least 2");
  o.schedule.reset();
  o.scenario = "highway";
  ExpectFailure(o, "unknown scenario 'highway'");
  o.scenario = "paper";
  o.config_path = "/nonexistent.yaml";
  ExpectFailure(o, "cannot open configuration file /nonexistent.yaml");
  EXPECT_FALSE(std::filesystem::exists(o.out_dir));
  // An --out that cannot be written is found before the run, not after all its computation.
  o.config_path.reset();
  const std::string file = TempPath("out_is_a_file");
  std::ofstream(file) << "x";
  o.out_dir = file + "/results";
  o.frames = 0;
  ExpectFailure(o, "cannot create the output folder " + file + "/results");
}

TEST(SimCommand, BinaryRejectsBadArgumentsWithoutCrashing) {
  const std::string bin = DSLAM_BINARY;
  // CLI11 and our own checks exit non-zero with a message; a crash would give a signal status.
  for (const char* args : {"sim --schedule window:1", "sim --mode wobbly", "sim --scenario highway", "sim --sigma -1",
                           "sim --frames -3", "nonsense"}) {
    const int status = std::system((bin + " " + args + " --out " + TempPath("cli") + " > /dev/null 2>&1").c_str());
    ASSERT_TRUE(WIFEXITED(status)) << args;
    EXPECT_NE(WEXITSTATUS(status), 0) << args;
  }
  EXPECT_EQ(std::system((bin + " sim --help > /dev/null").c_str()), 0);
}

TEST(SimCommand, WritesResultsAndPrintsTheTable) {
  SimCommandOptions o;
  o.frames = 20;
  o.out_dir = TempPath("ok");
  o.quiet = true;
  std::ostringstream out, err;
  ASSERT_EQ(RunSimCommand(o, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("static-only"), std::string::npos);
  EXPECT_NE(out.str().find("mode constant"), std::string::npos);  // the paper scenario's own default
  for (const char* f : {"metrics.json", "camera_gt.tum", "camera_ours.tum", "object_motions.csv", "object_speeds.csv"})
    EXPECT_TRUE(std::filesystem::exists(o.out_dir + "/" + f)) << f;
  std::filesystem::remove_all(o.out_dir);
}

}  // namespace
}  // namespace dslam
