// ServeNode's construction fails cleanly: an error naming what could not be created, no thread left
// running (a reader that cannot be created used to end in std::terminate).
#include "plugin/serve_node.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>

#include "app/dds_commands.h"
#include "output/dir_lock.h"
#include "plugin/topics.h"

#include "support/child_process.h"
#include "support/dds_domain.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

TEST(ServeNode, AReaderThatCannotBeCreatedIsAnErrorNotACrash) {
  std::string xml = test::ReadFile(std::string(DSLAM_SOURCE_DIR) + "/config/dds_profiles.xml");
  const std::string from = "profile_name=\"sensor_reader\"";
  const size_t at = xml.find(from);
  ASSERT_NE(at, std::string::npos);
  xml.replace(at, from.size(), "profile_name=\"renamed_reader\"");
  const std::string profiles = test::TempPath("no_sensor_reader.xml");
  std::ofstream(profiles) << xml;

  ServeOptions options;
  options.domain_id = test::DomainFor(test::DdsTestSlot::kServeNodeErrors);
  options.profiles_file = profiles;
  options.vehicles = {"a", "b"};
  options.out_dir = test::TempPath("serve_node_out");
  try {
    ServeNode node(options, RunConfig{});
    FAIL() << "a serve node without its sensor reader profile was created";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("sensor_reader"), std::string::npos) << e.what();
  }
}

TEST(ServeNode, AVehicleNameIsARos2NamespaceNotAPathOutOfOut) {
  // `--vehicle ..` wrote its results outside --out.
  for (const char* good : {"", "car1", "fleet/car_2", "_x"}) EXPECT_EQ(FindInvalidVehicleName(good), "") << good;
  for (const char* bad : {"..", "../x", "/abs", "a//b", "a/", "1car", "car-1", "car 1", "a/./b"})
    EXPECT_NE(FindInvalidVehicleName(bad), "") << bad;
  ServeOptions options;
  options.domain_id = test::DomainFor(test::DdsTestSlot::kServeNodeErrors);
  options.vehicles = {".."};
  options.out_dir = test::TempPath("serve_node_bad_vehicle");
  try {
    ServeNode node(options, RunConfig{});
    FAIL() << "a vehicle named '..' was served";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("vehicle name '..' is not a ROS 2 namespace"), std::string::npos) << e.what();
  }
}

// README, "Exit status": `serve` exits 2 on bad options and 4 when it cannot run (an output folder in use).
TEST(ServeCommand, ExitsTwoOnBadOptionsAndFourWhenItsOutputFolderIsInUse) {
  const std::string dir = test::TempPath("serve_command_exit");
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/calib.txt") << "P0: 721.5 0 609.6 0 0 721.5 172.9 0 0 0 1 0\n"
                                    << "P1: 721.5 0 609.6 0 0 721.5 172.9 0 0 0 1 0\n"
                                    << "P2: 721.5 0 609.6 0 0 721.5 172.9 0 0 0 1 0\n"
                                    << "P3: 721.5 0 609.6 0 0 721.5 172.9 0 0 0 1 0\n"
                                    << "R0_rect: 1 0 0 0 1 0 0 0 1\n";
  ServeCommandOptions options;
  options.calib_path = dir + "/calib.txt";
  options.domain_id = test::DomainFor(test::DdsTestSlot::kServeNodeErrors);
  options.profiles_file = std::string(DSLAM_SOURCE_DIR) + "/config/dds_profiles.xml";
  options.vehicles = {"v"};
  options.out_dir = dir + "/out";
  options.max_run_s = 0.5;
  std::ostringstream out, err;
  ServeCommandOptions bad = options;
  bad.max_pending_mb = 1;
  EXPECT_EQ(RunServeCommand(bad, out, err), 2) << err.str();
  // Ranges checked by the command itself too (for callers that build the options): 2, not 4 or a run.
  for (auto spoil : std::vector<std::function<void(ServeCommandOptions&)>>{
           [](ServeCommandOptions& o) { o.frame_rate_hz = 0.0; }, [](ServeCommandOptions& o) { o.max_run_s = -5.0; },
           [](ServeCommandOptions& o) { o.status_every_s = -1.0; },
           [&](ServeCommandOptions& o) { o.out_dir = dir + "/calib.txt"; }}) {
    bad = options;
    spoil(bad);
    EXPECT_EQ(RunServeCommand(bad, out, err), 2) << err.str();
  }
  EXPECT_NE(err.str().find("is a file, not a folder"), std::string::npos) << err.str();
  bad = options;
  bad.ros_distro = "melodic";  // ROS 1: no graph topic to speak of
  EXPECT_EQ(RunServeCommand(bad, out, err), 2) << err.str();
  EXPECT_NE(err.str().find("unknown ROS 2 distribution 'melodic'"), std::string::npos) << err.str();
  bad = options;
  bad.node_name = "dslam/front";  // a namespace belongs to --vehicle
  EXPECT_EQ(RunServeCommand(bad, out, err), 2) << err.str();
  EXPECT_NE(err.str().find("--node-name: node name 'dslam/front' is not a ROS 2 node name"), std::string::npos)
      << err.str();
  bad = options;
  std::ofstream(dir + "/batch.yaml") << "backend:\n  schedule: batch\n";
  bad.config_path = dir + "/batch.yaml";  // serve publishes each frame's estimate: no offline schedule
  EXPECT_EQ(RunServeCommand(bad, out, err), 2) << err.str();
  EXPECT_NE(err.str().find("batch.yaml: backend.schedule batch is an offline schedule"), std::string::npos) << err.str();
  bad = options;
  // Masks from a LiDAR whose pose the calibration does not give.
  bad.config_path = std::string(DSLAM_SOURCE_DIR) + "/config/kitti_raw_traffic.yaml";
  EXPECT_EQ(RunServeCommand(bad, out, err), 2) << err.str();
  EXPECT_NE(err.str().find("masks.source lidar_clusters needs Tr_velo_to_cam"), std::string::npos) << err.str();
  bad = options;
  bad.ownership_strength = 5;  // a hot standby's strength with a profile of SHARED ownership does nothing
  EXPECT_EQ(RunServeCommand(bad, out, err), 2) << err.str();
  EXPECT_NE(err.str().find("--ownership-strength has no effect with"), std::string::npos) << err.str();
  // (With config/dds_profiles_hot_standby.xml it runs: tests/network/hot_standby_test.cpp. Not here: Fast DDS keeps
  // the first file's profiles of a name for the whole process.)
  const DirLock taken(options.out_dir + "/v");
  EXPECT_EQ(RunServeCommand(options, out, err), 4) << err.str();
  EXPECT_NE(err.str().find("is in use by another process"), std::string::npos) << err.str();
}

TEST(ServeNode, TwoNodesCannotWriteOneVehicleFolder) {
  ServeOptions options;
  options.domain_id = test::DomainFor(test::DdsTestSlot::kServeNodeErrors);
  options.profiles_file = std::string(DSLAM_SOURCE_DIR) + "/config/dds_profiles.xml";
  options.vehicles = {"v"};
  options.out_dir = test::TempPath("serve_node_shared_out");
  ServeNode first(options, RunConfig{});
  try {
    ServeNode second(options, RunConfig{});
    FAIL() << "two nodes write one folder";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(options.out_dir + "/v is in use by another process"), std::string::npos)
        << e.what();
  }
  std::ostringstream log;
  first.shutdown(log);
}

}  // namespace
}  // namespace dslam
