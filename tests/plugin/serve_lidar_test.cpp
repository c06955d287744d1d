// serve with masks made from a LiDAR topic (masks.source: lidar_clusters): `dslam publish` replays real
// KITTI traffic frames with their Velodyne scans (sensor_msgs/PointCloud2 in the LiDAR's frame) and serve
// estimates exactly what `dslam run` estimates from the same files (skipped when ../shared/data is absent).
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <thread>

#include "app/run_command.h"
#include "output/trajectory_io.h"
#include "plugin/point_cloud_message.h"
#include "support/child_process.h"
#include "support/dds_domain.h"
#include "support/dds_profiles.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;
using namespace std::chrono_literals;
const std::string kTraffic = std::string(DSLAM_SHARED_DATA_DIR) + "/kitti_raw_2011_09_26_traffic";

TEST(PointCloudMessage, RoundTripAndBadClouds) {
  const std::vector<Eigen::Vector4f> scan = {{1.0f, 2.0f, 3.0f, 0.5f}, {-4.0f, 5.5f, 0.25f, 0.0f}};
  sensor_msgs::msg::PointCloud2 msg = EncodePointCloud(scan, 1'500'000'000, "lidar");
  DecodedPointCloud decoded = DecodePointCloud(msg);
  ASSERT_EQ(decoded.error, "");
  ASSERT_EQ(decoded.points.size(), 2u);
  EXPECT_EQ(decoded.points[1], scan[1]);
  // Fields at other offsets, a padded point and no intensity: as other drivers lay them out.
  sensor_msgs::msg::PointCloud2 other = msg;
  other.fields().pop_back();  // no intensity
  other.point_step(20);
  other.row_step(40);
  other.data().assign(40, 0);
  for (int i = 0; i < 2; ++i) std::memcpy(other.data().data() + 20 * i, scan[static_cast<size_t>(i)].data(), 12);
  decoded = DecodePointCloud(other);
  ASSERT_EQ(decoded.error, "");
  EXPECT_EQ(decoded.points[0], Eigen::Vector4f(1.0f, 2.0f, 3.0f, 0.0f));
  // A "no return" point (NaN) is left out.
  float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(other.data().data() + 20, &nan, 4);
  EXPECT_EQ(DecodePointCloud(other).points.size(), 1u);
  // Bad clouds: an error naming the scan and the problem, never a throw or a read past the data.
  sensor_msgs::msg::PointCloud2 bad = msg;
  bad.data().pop_back();
  EXPECT_NE(DecodePointCloud(bad).error.find("LiDAR scan at 1500000000 ns: 31 bytes of data"), std::string::npos)
      << DecodePointCloud(bad).error;
  bad = msg;
  bad.fields()[2].datatype(8);  // z as float64
  EXPECT_NE(DecodePointCloud(bad).error.find("field 'z' is not one float32"), std::string::npos);
  bad = msg;
  bad.fields()[1].offset(14);  // y past the 16-byte point
  EXPECT_NE(DecodePointCloud(bad).error.find("field 'y' at offset 14 lies outside"), std::string::npos);
  bad = msg;
  bad.fields().erase(bad.fields().begin());
  EXPECT_NE(DecodePointCloud(bad).error.find("no field 'x'"), std::string::npos);
  bad = msg;
  bad.row_step(8);
  EXPECT_NE(DecodePointCloud(bad).error.find("row_step 8 is smaller"), std::string::npos);
  bad = msg;
  bad.width(5'000'000);
  EXPECT_NE(DecodePointCloud(bad).error.find("more than the"), std::string::npos);
  bad = msg;
  bad.is_bigendian(true);
  EXPECT_NE(DecodePointCloud(bad).error.find("big-endian"), std::string::npos);
}

TEST(ServeLidar, MasksFromTheLidarTopicGiveWhatTheRunGivesFromTheFiles) {
  if (!fs::exists(kTraffic + "/velodyne_points")) GTEST_SKIP() << "shared data absent: " << kTraffic;
  constexpr int kFrames = 12;
  const std::string config = std::string(DSLAM_SOURCE_DIR) + "/config/kitti_raw_traffic.yaml";

  RunCommandOptions run;
  run.dataset_dir = kTraffic;
  run.config_path = config;
  run.frames = kFrames;
  run.out_dir = test::TempPath("serve_lidar_run");
  run.methods = {"ours"};
  run.no_figures = true;
  run.quiet = true;
  std::ostringstream out, err;
  ASSERT_EQ(RunRunCommand(run, out, err), 0) << err.str();

  const std::string domain = std::to_string(test::DomainFor(test::DdsTestSlot::kServeLidar));
  const std::string profiles = test::WithLosslessSensorStreams(std::string(DSLAM_SOURCE_DIR) + "/config/dds_profiles.xml",
                                                               test::TempPath("serve_lidar_profiles.xml"));
  const std::string served = test::TempPath("serve_lidar_out"), log = test::TempPath("serve_lidar.log");
  test::Process serve({"serve", "--domain", domain, "--profiles", profiles, "--calib", kTraffic + "/calib.txt", "--config",
                       config, "--no-odometry", "--every-frame", "--out", served, "--status-every", "0",
                       "--max-pending", "64", "--max-pending-mb", "2048", "--timeout-ms", "5000", "--silence-ms", "30000"},
                      log);
  test::Process publish({"publish", "--domain", domain, "--profiles", profiles, "--dataset", kTraffic, "--config", config,
                         "--frames",
                         std::to_string(kFrames), "--rate", "4", "--wait", "60"},
                        test::TempPath("serve_lidar_publish.log"));
  ASSERT_EQ(publish.wait(180s), 0) << test::ReadFile(test::TempPath("serve_lidar_publish.log"));
  // Every frame estimated: its pose is on disk once it left the window, the rest when serve stops.
  std::this_thread::sleep_for(10s);
  serve.signal(SIGTERM);
  ASSERT_EQ(serve.wait(120s), 0) << test::ReadFile(log);
  EXPECT_NE(test::ReadFile(log).find(std::to_string(kFrames) + " frames, results written to"), std::string::npos)
      << test::ReadFile(log);

  std::vector<int64_t> run_t, served_t;
  const std::vector<SE3> from_files = ReadTumTrajectory(run.out_dir + "/camera_ours.tum", &run_t);
  const std::vector<SE3> from_topics = ReadTumTrajectory(served + "/default/camera_ours.tum", &served_t);
  ASSERT_EQ(from_files.size(), static_cast<size_t>(kFrames));
  ASSERT_EQ(from_topics.size(), from_files.size());
  for (size_t k = 0; k < from_files.size(); ++k) {
    EXPECT_EQ(served_t[k], run_t[k]);
    EXPECT_LT((from_topics[k].translation() - from_files[k].translation()).norm(), 1e-6) << "frame " << k;
  }
  // The objects too: the same rows of speeds (the masks made from the topic's scans are the files'
  // masks); serve writes them frame by frame as they leave the window, run object by object.
  auto rows = [](const std::string& path) {
    std::istringstream in(test::ReadFile(path));
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    std::sort(lines.begin(), lines.end());
    return lines;
  };
  const std::vector<std::string> served_rows = rows(served + "/default/object_speeds.csv");
  EXPECT_GT(served_rows.size(), static_cast<size_t>(2 * kFrames));  // several vehicles a frame
  EXPECT_EQ(served_rows, rows(run.out_dir + "/object_speeds.csv"));
}

}  // namespace
}  // namespace dslam
