// The README's "Exit status" table, checked against the binary as a user runs it (`serve`'s status 4:
// tests/plugin/serve_node_test.cpp).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "output/dir_lock.h"
#include "support/child_process.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

// The exit status of `dslam ARGS` run by the shell with `env` before it; -1 when it did not exit (a crash).
int Status(const std::string& args, const std::string& env = "") {
  const std::string command = env + " " + DSLAM_BINARY + " " + args + " > /dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(ExitStatus, EveryCommandEndsWithAStatusOfTheReadmeTable) {
  const std::string dir = test::TempPath("exit_status");
  std::filesystem::create_directories(dir);
  const std::string out = " --out " + dir + "/results";
  // 0: done, --help included.
  EXPECT_EQ(Status("--help"), 0);
  EXPECT_EQ(Status("run --help"), 0);
  EXPECT_EQ(Status("sim --frames 5 --quiet --no-figures" + out), 0);
  // 2: bad input, named.
  EXPECT_EQ(Status("nonsense"), 2);
  EXPECT_EQ(Status("sim --no-such-option"), 2);
  EXPECT_EQ(Status("sim --frames -3" + out), 2);
  EXPECT_EQ(Status("sim --sigma nan" + out), 2);
  EXPECT_EQ(Status("run --dataset " + dir + "/missing" + out), 2);
  std::ofstream(dir + "/bad.yaml") << "backend: [unclosed\n";
  EXPECT_EQ(Status("sim --frames 5 --config " + dir + "/bad.yaml" + out), 2);
  std::ofstream(dir + "/a_file") << "x";
  EXPECT_EQ(Status("sim --frames 5 --out " + dir + "/a_file/results"), 2);
  EXPECT_EQ(Status("figures " + dir + "/missing"), 2);
  EXPECT_EQ(Status("study --dataset " + dir + "/missing" + out), 2);
  EXPECT_EQ(Status("study --dataset " + dir + " --frames -1" + out), 2);
  EXPECT_EQ(Status("study --dataset " + dir + out), 2);  // not a rendered scene with a stereo pair and exact flow
  // 3: results written, figures not drawn (no Xvfb to be found, no display).
  EXPECT_EQ(Status("sim --frames 5 --quiet" + out, "env -u DISPLAY PATH=/nonexistent"), 3);
  EXPECT_TRUE(std::filesystem::exists(dir + "/results/metrics.json"));
  std::filesystem::remove_all(dir);
}


// 4: an output folder another process writes (here: this test holds its lock) is refused by every command
// that writes one, naming it, before anything runs; free again, the same folder is taken.
TEST(ExitStatus, EveryCommandRefusesAnOutputFolderInUseWithStatus4) {
  const std::string dir = test::TempPath("exit_status_in_use");
  const std::string busy = dir + "/busy", data = dir + "/empty_dataset";  // exists: options pass their checks
  std::filesystem::create_directories(data);
  const std::vector<std::vector<std::string>> commands = {
      {"sim", "--frames", "5", "--quiet", "--no-figures", "--out", busy},
      {"kitti-replay", "--data", data, "--seq", "0000", "--out", busy},
      {"run", "--dataset", data, "--out", busy},
      {"render-scene", "--scenario", "city", "--frames", "2", "--out", busy},
      {"study", "--dataset", data, "--out", busy},
      {"lidar-check", "--dataset", data, "--out", busy},
      {"figures", busy}};
  {
    const DirLock held(busy);
    for (const auto& args : commands) {
      const std::string log = dir + "/" + args[0] + ".log";
      test::Process p(args, log);
      EXPECT_EQ(p.wait(std::chrono::seconds(60)), 4) << args[0] << ": " << test::ReadFile(log);
      EXPECT_NE(test::ReadFile(log).find("output folder " + busy + " is in use by another process"), std::string::npos)
          << test::ReadFile(log);
    }
    // The figures of a run are drawn by its child (the hidden --for-parent), into the folder the run holds;
    // here this test is that parent. (Nothing to draw in it: status 2, not 4.)
    const std::string log = dir + "/figures_for_parent.log";
    test::Process p({"figures", busy, "--for-parent"}, log);
    EXPECT_EQ(p.wait(std::chrono::seconds(60)), 2) << test::ReadFile(log);
    EXPECT_EQ(test::ReadFile(log).find("in use"), std::string::npos) << test::ReadFile(log);
  }
  EXPECT_EQ(Status("sim --frames 5 --quiet --no-figures --out " + busy), 0);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace dslam
