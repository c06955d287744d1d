// `dslam publish`: rates and waits outside a sensor's range are refused (2), DDS that cannot start is status 4
// as for serve, and a stop signal is answered at once whatever the rate.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <fstream>
#include <thread>
#include <tuple>
#include <vector>

#include "support/child_process.h"
#include "support/dds_domain.h"
#include "support/rendered_city.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
using namespace std::chrono_literals;

std::vector<std::string> Publish(const std::string& dataset, const std::string& rate, const std::string& wait) {
  return {"publish", "--dataset", dataset, "--rate", rate, "--wait", wait, "--domain",
          std::to_string(test::DomainFor(test::DdsTestSlot::kPublishStop))};
}

TEST(PublishCommand, RefusesRatesAndWaitsNoSensorHas) {
  const std::string dataset = test::RenderedCity("publish_city", 3);
  const std::string log = test::TempPath("publish_bad.log");
  for (const auto& [rate, wait, what] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"1e-9", "0", "--rate"}, {"nan", "0", "--rate"}, {"5000", "0", "--rate"}, {"10", "nan", "--wait"},
           {"10", "-1", "--wait"}}) {
    test::Process p(Publish(dataset, rate, wait), log);
    EXPECT_EQ(p.wait(30s), 2) << rate << " " << wait << ": " << test::ReadFile(log);
    EXPECT_NE(test::ReadFile(log).find(what), std::string::npos) << test::ReadFile(log);
  }
}

TEST(PublishCommand, StopsAtOnceOnSigtermEvenAtALowRate) {
  const std::string dataset = test::RenderedCity("publish_city", 3);
  const std::string log = test::TempPath("publish_slow.log");
  test::Process p(Publish(dataset, "0.01", "0"), log);  // a frame every 100 s
  std::this_thread::sleep_for(2s);
  ASSERT_TRUE(p.running()) << test::ReadFile(log);
  const auto t0 = std::chrono::steady_clock::now();
  p.signal(SIGTERM);
  EXPECT_EQ(p.wait(20s), 0) << test::ReadFile(log);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 5s);
}


// The README's table: DDS that cannot start (here: Fast DDS cannot load the profiles file) is 4 for publish
// as for serve, in one line naming the file; bad options stay 2.
TEST(PublishCommand, DdsThatCannotStartIsStatusFour) {
  const std::string dataset = test::RenderedCity("publish_city", 3);
  const std::string profiles = test::TempPath("publish_broken_profiles.xml"), log = test::TempPath("publish_dds.log");
  std::ofstream(profiles) << "<?xml version=\"1.0\"?>\n<dds><profiles><participant profile_name=";
  std::vector<std::string> args = Publish(dataset, "10", "0");
  args.insert(args.end(), {"--profiles", profiles});
  test::Process p(args, log);
  EXPECT_EQ(p.wait(30s), 4) << test::ReadFile(log);
  EXPECT_NE(test::ReadFile(log).find("cannot load the Fast DDS profiles " + profiles), std::string::npos)
      << test::ReadFile(log);
  // One line of ours, quoting Fast DDS; not its own coloured log lines.
  EXPECT_EQ(test::ReadFile(log).find("XMLPARSER"), std::string::npos) << test::ReadFile(log);
}

}  // namespace
}  // namespace dslam
