// DDS Security with the test CA of scripts/make_dds_security.sh: a participant without valid
// credentials cannot inject frames (serve never receives a sample), one with credentials can.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "support/child_process.h"
#include "support/dds_domain.h"
#include "support/dds_profiles.h"
#include "support/rendered_city.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;
using namespace std::chrono_literals;

TEST(DdsSecurity, OnlyAuthenticatedParticipantsCanInjectFrames) {
  const std::string script = std::string(DSLAM_SOURCE_DIR) + "/scripts/make_dds_security.sh";
  const std::string certs = test::TempPath("dds_security"), intruder = test::TempPath("dds_intruder");
  ASSERT_EQ(std::system((script + " " + certs + " serve publisher > /dev/null").c_str()), 0);
  ASSERT_EQ(std::system((script + " " + intruder + " publisher > /dev/null").c_str()), 0);  // another CA

  const std::string dataset = test::RenderedCity("dds_security_city", 5);
  const std::string domain = std::to_string(test::DomainFor(test::DdsTestSlot::kSecurity));
  const std::string out = test::TempPath("dds_security_out");
  // serve must count all 20 samples of the trusted publisher (see WithLosslessSensorStreams).
  const std::string serve_profiles =
      test::WithLosslessSensorStreams(certs + "/serve_profiles.xml", certs + "/serve_lossless_profiles.xml");
  const std::string trusted_profiles =
      test::WithLosslessSensorStreams(certs + "/publisher_profiles.xml", certs + "/publisher_lossless_profiles.xml");
  test::Process serve({"serve", "--domain", domain, "--profiles", serve_profiles, "--calib",
                       dataset + "/calib.txt", "--out", out, "--status-every", "0", "--every-frame"},
                      test::TempPath("secure_serve.log"));
  // --wait: how long a publisher looks for serve's readers; one without valid credentials never finds them.
  auto publish = [&](const std::string& profiles, const std::string& log, const std::string& wait_s) {
    test::Process p({"publish", "--domain", domain, "--profiles", profiles, "--dataset", dataset, "--wait", wait_s},
                    log);
    return p.wait(90s);
  };
  // Without security, and with a certificate from a CA serve does not trust: the publisher finds no
  // reader to match, publishes into the void and serve receives nothing.
  EXPECT_EQ(publish(std::string(DSLAM_SOURCE_DIR) + "/config/dds_profiles.xml", test::TempPath("plain.log"), "4"), 0);
  EXPECT_EQ(publish(intruder + "/publisher_profiles.xml", test::TempPath("intruder.log"), "4"), 0);
  EXPECT_EQ(publish(trusted_profiles, test::TempPath("trusted.log"), "30"), 0);
  std::this_thread::sleep_for(3s);  // let serve finish the frames
  serve.signal(SIGTERM);
  ASSERT_EQ(serve.wait(60s), 0) << test::ReadFile(test::TempPath("secure_serve.log"));

  std::ifstream in(out + "/default/metrics.json");
  ASSERT_TRUE(in) << test::ReadFile(test::TempPath("secure_serve.log"));
  const nlohmann::json run = nlohmann::json::parse(in)["run"];
  EXPECT_EQ(run["frames_received"].get<int>(), 20);  // 5 frames x 4 topics, all from the trusted publisher
  EXPECT_EQ(run["frames"].get<int>(), 5);
  EXPECT_EQ(run["rejected_invalid"].get<int>(), 0);
}

}  // namespace
}  // namespace dslam
