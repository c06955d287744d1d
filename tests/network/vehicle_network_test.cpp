// The vehicle network: a camera host (dslam publish), a compute host (dslam serve) and a display host (dslam
// listen), each a network namespace on one bridge (tests/support/network_hosts.h), Fast DDS over UDP between them
// with multicast discovery, KITTI-size frames of the rendered city at 10 Hz on links capped at 100 Mbit/s, with
// the vehicle-network profile (config/dds_profiles_vehicle_network.xml) and JPEG colour. serve estimates every
// frame that arrives whole (--every-frame): what these tests count is the network's doing, not the CPU's, which
// ctest shares with other tests (bench_vehicle_network measures serve's own newest-frame-wins mode). Skipped where
// this process cannot make network namespaces.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "support/child_process.h"
#include "support/network_hosts.h"
#include "support/rendered_city.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;
using namespace std::chrono_literals;

const std::string kNetworkProfiles = std::string(DSLAM_SOURCE_DIR) + "/config/dds_profiles_vehicle_network.xml";
constexpr int kFrames = 60;

struct NetworkRun {
  int publish_exit = -1, serve_exit = -1, listen_exit = -1;
  bool discovered = false;  // the display host matched serve's writer
  nlohmann::json serve;     // metrics.json's "run"
  nlohmann::json listen;    // listen.json
  std::set<int64_t> listened_stamps;
  std::string logs;  // for failure messages
};

const std::string kDefaultProfiles = std::string(DSLAM_SOURCE_DIR) + "/config/dds_profiles.xml";

// publish -> serve -> listen across three hosts with `loss_percent` of Ethernet frames dropped at the bridge.
NetworkRun RunThreeHosts(const std::string& name, double loss_percent, const std::string& profiles = kNetworkProfiles,
                         const std::string& compress = "jpeg", bool multicast = true) {
  const std::string city = test::RenderedCity("network_city", kFrames, 1);
  const std::string dir = test::TempPath(name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  test::NetworkHosts net({"camera", "compute", "display"});
  for (const char* host : {"camera", "compute", "display"}) net.setBandwidth(host, 100.0);
  net.setLoss(loss_percent);
  net.setMulticast(multicast);
  NetworkRun run;
  test::Process serve(net.launcher(),
                      net.on("compute", DSLAM_BINARY,
                             {"serve", "--calib", city + "/calib.txt", "--profiles", profiles, "--out", dir + "/serve",
                              "--status-every", "0", "--every-frame"}),
                      dir + "/serve.log");
  test::Process listen(net.launcher(),
                       net.on("display", DSLAM_BINARY,
                              {"listen", "--profiles", profiles, "--out", dir + "/listen", "--idle-stop", "5",
                               "--max-run", "300", "--status-every", "0"}),
                       dir + "/listen.log");
  // The estimates are not kept for late subscribers: the display host and serve must have matched each other
  // first, both ways (discovery is not symmetric: the display host can see serve's writer before that writer has
  // seen the display host's reader, and the estimates written in between are not for it).
  const auto discovery = multicast ? 60s : 15s;
  const bool matched = test::WaitForLogLine(dir + "/listen.log", "1 writer of estimates matched", discovery) &&
                       test::WaitForLogLine(dir + "/serve.log", "1 reader of camera estimates matched", discovery);
  run.discovered = matched;
  if (matched) {
    test::Process publish(net.launcher(),
                          net.on("camera", DSLAM_BINARY,
                                 {"publish", "--dataset", city, "--profiles", profiles, "--rate", "10", "--compress",
                                  compress, "--stamp-now", "--wait", "60"}),
                          dir + "/publish.log");
    run.publish_exit = publish.wait(180s);
  }
  // serve stops first (it estimates what it has assembled, and publishes it), then the display host, which ends
  // 5 s after the last estimate: everything serve published had the time to arrive.
  std::this_thread::sleep_for(3s);
  serve.signal(SIGTERM);
  run.serve_exit = serve.wait(120s);
  run.listen_exit = listen.wait(10s);
  if (run.listen_exit == -1) listen.signal(SIGTERM), run.listen_exit = listen.wait(30s);  // nothing received
  run.serve = test::ReadJsonObject(dir + "/serve/default/metrics.json")["run"];
  run.listen = test::ReadJsonObject(dir + "/listen/listen.json");
  if (!run.serve.is_object()) run.serve = nlohmann::json::object();  // nothing estimated: no metrics.json
  std::ifstream csv(dir + "/listen/estimates.csv");
  std::string line;
  std::getline(csv, line);  // header
  while (std::getline(csv, line)) run.listened_stamps.insert(std::stoll(line.substr(0, line.find(','))));
  for (const char* log : {"serve.log", "listen.log", "publish.log"})
    run.logs += std::string("--- ") + log + "\n" + test::ReadFile(dir + "/" + log);
  std::cout << name << ": serve estimated " << run.serve.value("frames", 0) << " of " << kFrames
            << " frames; serve: " << run.serve.dump() << "; display host: " << run.listen.dump() << std::endl;
  return run;
}

class VehicleNetwork : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const std::string why = test::NetworkHosts::WhyUnavailable(); !why.empty()) GTEST_SKIP() << why;
  }
};

// What serve estimated reached the display host, once each: the subscriber's frames are serve's.
void ExpectSubscriberHasWhatServeEstimated(const NetworkRun& run) {
  ASSERT_TRUE(run.listen.contains("frames")) << run.logs;
  EXPECT_EQ(run.listen.value("frames", -1), run.serve.value("frames", -2)) << run.logs;
  EXPECT_EQ(run.listen.value("repeated", -1), 0) << run.logs;
  EXPECT_EQ(run.listen.value("out_of_order", -1), 0) << run.logs;
  EXPECT_EQ(run.listened_stamps.size(), run.listen.value("frames", 0u)) << run.logs;
}

TEST_F(VehicleNetwork, ThreeHostsAtTenHzOn100MbitLinksEstimateEveryFrame) {
  const NetworkRun run = RunThreeHosts("network_clean", 0.0);
  ASSERT_EQ(run.publish_exit, 0) << run.logs;
  ASSERT_EQ(run.serve_exit, 0) << run.logs;
  EXPECT_EQ(run.listen_exit, 0) << run.logs;
  ASSERT_TRUE(run.serve.contains("frames")) << run.logs;
  EXPECT_EQ(run.serve.value("frames", 0), kFrames) << run.logs;
  EXPECT_EQ(run.listen.value("frames", 0), kFrames) << run.logs;  // (stamps are the camera host's wall clock:
  // on a loaded machine their steps vary, so frames missing "between stamps" are not counted on them here)
  ExpectSubscriberHasWhatServeEstimated(run);
  // The capture stamps are the camera host's clock, which the display host shares here.
  EXPECT_GT(run.listen["capture_to_receipt_ms"].value("frames", 0), 0) << run.logs;
}

// Why the vehicle-network profile: with the default one (best-effort sensor readers, 64 KB datagrams of ~45
// Ethernet frames each) a sample of hundreds of Ethernet frames almost never arrives whole at 1 % loss. Also
// proves that the loss is real.
TEST_F(VehicleNetwork, OnePercentLostWithBestEffortSensorsLosesMostFrames) {
  const NetworkRun run = RunThreeHosts("network_loss1_best_effort", 1.0, kDefaultProfiles, "png");
  ASSERT_EQ(run.publish_exit, 0) << run.logs;
  EXPECT_EQ(run.serve_exit, 0) << run.logs;
  EXPECT_LT(run.serve.value("frames", 0), kFrames / 2) << run.logs;
}

TEST_F(VehicleNetwork, OnePercentOfEthernetFramesLostStillEstimatesAtLeast95PercentOfFrames) {
  const NetworkRun run = RunThreeHosts("network_loss1", 1.0);
  ASSERT_EQ(run.publish_exit, 0) << run.logs;
  ASSERT_EQ(run.serve_exit, 0) << run.logs;
  ASSERT_TRUE(run.serve.contains("frames")) << run.logs;
  EXPECT_GE(run.serve.value("frames", 0), 57) << run.logs;  // 95 % of 60
  ExpectSubscriberHasWhatServeEstimated(run);
}

// At 5 % loss serve keeps running, estimates most frames, and every frame some of whose samples reached it is
// estimated or counted. A frame can also vanish whole on the way, which serve cannot count: a keep-last writer
// that overwrites a sample before its repair sends a GAP, which the reader takes as "not relevant", not as lost,
// and a publisher may write before serve's readers have discovered it (discovery is not symmetric). Over 37 runs
// on a 2-core machine, every frame was estimated or counted in 32; in five, 4 to 15 frames never reached serve
// (45-56 estimated). So the bound below is half (the default profile gets 0-2 through at 1 %), and the identity
// is asserted on the samples that arrived.
TEST_F(VehicleNetwork, FivePercentLostKeepsServeRunningAndEveryFrameThatReachedItIsEstimatedOrCounted) {
  const NetworkRun run = RunThreeHosts("network_loss5", 5.0);
  ASSERT_EQ(run.publish_exit, 0) << run.logs;
  EXPECT_EQ(run.serve_exit, 0) << run.logs;  // it ran until told to stop, and wrote its results
  ASSERT_TRUE(run.serve.contains("frames")) << run.logs;
  const int estimated = run.serve.value("frames", 0);
  EXPECT_GE(estimated, kFrames / 2) << run.logs;
  // Each frame is four samples (colour, depth, mask, odometry); every sample that arrived belongs to a frame
  // that was estimated, dropped incomplete (counted) or dropped for the backlog (counted).
  const int accounted = estimated + run.serve.value("dropped_incomplete", 0) + run.serve.value("dropped_queue_full", 0);
  EXPECT_GE(4 * accounted, run.serve.value("frames_received", 0)) << run.logs;
  ExpectSubscriberHasWhatServeEstimated(run);
}

// The vehicle-network profile with the three hosts as initial peers: Fast DDS then also announces its participant
// to each of them by unicast (what a user writes where the network drops multicast).
std::string ProfilesWithInitialPeers(const std::string& dir) {
  std::string xml = test::ReadFile(kNetworkProfiles);
  const std::string peers =
      "        <builtin>\n          <initialPeersList>\n"
      "            <locator><udpv4><address>169.254.1.1</address></udpv4></locator>\n"
      "            <locator><udpv4><address>169.254.1.2</address></udpv4></locator>\n"
      "            <locator><udpv4><address>169.254.1.3</address></udpv4></locator>\n"
      "          </initialPeersList>\n        </builtin>\n";
  const size_t at = xml.find("      </rtps>");
  if (at == std::string::npos) return {};
  xml.insert(at, peers);
  const std::string path = dir + "/initial_peers_profiles.xml";
  std::ofstream(path) << xml;
  return path;
}

TEST_F(VehicleNetwork, WithoutMulticastTheHostsFindEachOtherByTheirInitialPeers) {
  const std::string dir = test::TempPath("network_peers_profiles");
  fs::create_directories(dir);
  // Multicast dropped: the shipped profile's discovery finds nothing.
  const NetworkRun lost = RunThreeHosts("network_no_multicast", 0.0, kNetworkProfiles, "jpeg", /*multicast=*/false);
  EXPECT_FALSE(lost.discovered) << lost.logs;
  // With the hosts' addresses as initial peers, every frame is estimated and reaches the display host.
  const std::string profiles = ProfilesWithInitialPeers(dir);
  ASSERT_FALSE(profiles.empty());
  const NetworkRun run = RunThreeHosts("network_initial_peers", 0.0, profiles, "jpeg", /*multicast=*/false);
  ASSERT_TRUE(run.discovered) << run.logs;
  ASSERT_EQ(run.publish_exit, 0) << run.logs;
  ASSERT_TRUE(run.serve.contains("frames")) << run.logs;
  EXPECT_EQ(run.serve.value("frames", 0), kFrames) << run.logs;
  ExpectSubscriberHasWhatServeEstimated(run);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dslam
