// The command line's own errors: exit status 2 (README) with a line that names the problem.
#include <gtest/gtest.h>

#include <chrono>

#include "support/child_process.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
using namespace std::chrono_literals;

struct Outcome {
  int status;
  std::string output;
};

Outcome Dslam(const std::vector<std::string>& args) {
  const std::string log = test::TempPath("cli.log");
  test::Process p(args, log);
  const int status = p.wait(60s);
  return {status, test::ReadFile(log)};
}

TEST(Cli, BadCommandsAndOptionsExitWithStatus2AndSaySo) {
  Outcome o = Dslam({"frobnicate"});
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.output.find("unknown command 'frobnicate'"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("run"), std::string::npos) << o.output;  // lists the commands

  o = Dslam({"run", "--dataset", DSLAM_SOURCE_DIR, "--bogus"});
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("--bogus"), std::string::npos) << o.output;

  const std::string calib = std::string(DSLAM_SOURCE_DIR) + "/README.md";  // exists; never read here
  for (const char* domain : {"300", "-1"}) {
    o = Dslam({"serve", "--calib", calib, "--domain", domain});
    EXPECT_EQ(o.status, 2) << domain << ": " << o.output;
    EXPECT_NE(o.output.find("--domain"), std::string::npos) << o.output;
  }
  o = Dslam({"sim", "--help"});
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("--scenario"), std::string::npos);
}

}  // namespace
}  // namespace dslam
