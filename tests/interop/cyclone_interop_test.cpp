// serve read by a ROS 2 node built on another DDS implementation: a Cyclone DDS client
// (tests/interop/cyclone_listener.c, types from ROS 2-faithful IDL, ROS 2's default subscription QoS),
// over UDP with shared memory off on the Fast DDS side, as a node on another host would read it.
#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "data/image_dataset.h"
#include "output/trajectory_io.h"
#include "support/child_process.h"
#include "support/dds_domain.h"
#include "support/dds_profiles.h"
#include "support/rendered_city.h"
#include "support/serve_reference.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
using namespace std::chrono_literals;

const std::string kProfiles = std::string(DSLAM_SOURCE_DIR) + "/config/dds_profiles.xml";

struct Decoded {
  std::map<int64_t, std::vector<double>> odometry;  // stamp -> x y z qx qy qz qw
  std::map<int64_t, int> objects_per_stamp;
  std::map<int64_t, std::vector<std::vector<std::string>>> objects_by_stamp;  // the object rows of each array
  std::map<int64_t, std::vector<std::vector<std::string>>> markers_by_stamp;  // the marker rows of each array
  std::vector<std::vector<std::string>> object_rows, status_rows, odometry_rows, objects_rows;
};

Decoded ReadDecoded(const std::string& path) {
  Decoded d;
  std::ifstream in(path);
  int64_t array_stamp = -1;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::vector<std::string> f;
    for (std::string x; fields >> x;) f.push_back(x);
    if (f.empty()) continue;
    const auto stamp = [&] { return std::stoll(f[1]) * 1'000'000'000LL + std::stoll(f[2]); };
    if (f[0] == "odometry" && f.size() == 12) {
      std::vector<double> pose;
      for (size_t i = 5; i < 12; ++i) pose.push_back(std::stod(f[i]));
      d.odometry[stamp()] = pose;
      d.odometry_rows.push_back(f);
    } else if (f[0] == "objects" && f.size() == 5) {
      array_stamp = stamp();
      d.objects_per_stamp[array_stamp] = std::stoi(f[4]);
      d.objects_by_stamp[array_stamp];
      d.objects_rows.push_back(f);
    } else if (f[0] == "object" && f.size() == 16) {
      d.object_rows.push_back(f);
      d.objects_by_stamp[array_stamp].push_back(f);
    } else if (f[0] == "markers" && f.size() == 4) {
      array_stamp = stamp();
      d.markers_by_stamp[array_stamp];
    } else if (f[0] == "marker" && f.size() >= 7) {
      d.markers_by_stamp[array_stamp].push_back(f);
    } else if (f[0] == "status" && f.size() == 12) {
      d.status_rows.push_back(f);
    } else {
      ADD_FAILURE() << path << ": unexpected line: " << line;
    }
  }
  return d;
}

// serve on `domain` with the given profiles, for the city in `dataset`; generous timeouts (a loaded machine).
std::vector<std::string> ServeArgs(int domain, const std::string& profiles, const std::string& dataset,
                                   const std::string& out) {
  return {"serve", "--domain", std::to_string(domain), "--profiles", profiles, "--calib", dataset + "/calib.txt",
          "--out", out, "--status-every", "0", "--max-pending", "64", "--max-pending-mb", "2048", "--timeout-ms",
          "5000", "--silence-ms", "30000", "--every-frame"};
}

// The Cyclone listener of serve's outputs, started first: it is volatile, as ROS 2's default, so it must have
// discovered serve before the estimates come.
std::unique_ptr<test::Process> StartListener(int domain, int frames, const std::string& decoded_path,
                                             const std::string& log) {
  auto listener = std::make_unique<test::Process>(
      DSLAM_CYCLONE_LISTENER, std::vector<std::string>{std::to_string(domain), "rt/", std::to_string(frames), "150",
                                                       decoded_path},
      log);
  std::this_thread::sleep_for(4s);
  return listener;
}

TEST(CycloneInterop, ARos2NodeOnCycloneDdsDecodesEveryEstimateObjectMotionAndStatusOverUdp) {
  constexpr int kFrames = 12;
  const std::string dataset = test::RenderedCity("cyclone_city_12", kFrames, 1);
  ASSERT_FALSE(dataset.empty());
  const int domain = test::DomainFor(test::DdsTestSlot::kCycloneListener);
  // Lossless sensor streams (the test compares every frame), and UDP only on the Fast DDS side.
  const std::string profiles = test::WithoutSharedMemory(
      test::WithLosslessSensorStreams(kProfiles, test::TempPath("cyclone_lossless.xml")),
      test::TempPath("cyclone_lossless_udp.xml"));
  const std::string out = test::TempPath("cyclone_serve_out");
  test::Process serve(ServeArgs(domain, profiles, dataset, out), test::TempPath("cyclone_serve.log"));
  const std::string decoded_path = test::TempPath("cyclone_decoded.txt");
  const auto listener = StartListener(domain, kFrames, decoded_path, test::TempPath("cyclone_listener.log"));
  test::Process publish({"publish", "--domain", std::to_string(domain), "--profiles", profiles, "--dataset", dataset,
                         "--rate", "5", "--wait", "60"},
                        test::TempPath("cyclone_publish.log"));
  ASSERT_EQ(publish.wait(120s), 0) << test::ReadFile(test::TempPath("cyclone_publish.log"));
  EXPECT_EQ(listener->wait(150s), 0) << test::ReadFile(test::TempPath("cyclone_listener.log"));
  serve.signal(SIGTERM);
  ASSERT_EQ(serve.wait(60s), 0) << test::ReadFile(test::TempPath("cyclone_serve.log"));

  const Decoded d = ReadDecoded(decoded_path);
  // Every camera estimate, equal to what serve published (its camera_ours_online.tum, 9 decimals).
  std::vector<int64_t> t_ns;
  const std::vector<SE3> published = ReadTumTrajectory(out + "/default/camera_ours_online.tum", &t_ns);
  ASSERT_EQ(published.size(), static_cast<size_t>(kFrames));
  ASSERT_EQ(d.odometry.size(), static_cast<size_t>(kFrames));
  for (size_t k = 0; k < published.size(); ++k) {
    const auto it = d.odometry.lower_bound(t_ns[k] - 1000);
    ASSERT_NE(it, d.odometry.end()) << k;
    ASSERT_LE(std::llabs(it->first - t_ns[k]), 1000) << k;
    const Vec3 t = published[k].translation();
    const auto q = published[k].rotation();
    const std::vector<double> expected = {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
    for (int i = 0; i < 7; ++i) EXPECT_NEAR(it->second[i], expected[i], 2e-9) << "frame " << k << " field " << i;
  }
  for (const auto& row : d.odometry_rows) {
    EXPECT_EQ(row[3], "world");
    EXPECT_EQ(row[4], "camera");
  }
  // One object array per frame, stamped as its camera estimate, in the world frame, every field decoded.
  ASSERT_EQ(d.objects_per_stamp.size(), static_cast<size_t>(kFrames));
  int objects = 0;
  for (const auto& [stamp, count] : d.objects_per_stamp) {
    EXPECT_TRUE(d.odometry.count(stamp)) << stamp;
    objects += count;
  }
  for (const auto& row : d.objects_rows) EXPECT_EQ(row[3], "world");
  ASSERT_EQ(d.object_rows.size(), static_cast<size_t>(objects));
  EXPECT_GT(objects, kFrames);  // the city has cars in view in every frame after the first
  for (const auto& row : d.object_rows) {
    EXPECT_GT(std::stoi(row[1]), 0);
    EXPECT_TRUE(row[2] == "0" || row[2] == "1");
    const double speed = std::stod(row[3]), vx = std::stod(row[4]), vy = std::stod(row[5]), vz = std::stod(row[6]);
    EXPECT_NEAR(speed, std::sqrt(vx * vx + vy * vy + vz * vz), 1e-6 * std::max(1.0, speed));
    EXPECT_LE(std::abs(std::stod(row[10])), 1.0);  // the orientation's w of H
    EXPECT_GE(std::stod(row[11]), 0.0);             // covariance diagonal entries
    EXPECT_GE(std::stod(row[12]), 0.0);
    EXPECT_EQ(row[13], "1");                        // all 36 finite
    EXPECT_GT(std::stod(row[14]), 0.5);             // the object's centroid in the camera, in front of it
    EXPECT_GT(std::stoi(row[15]), 0);               // its mask's box in the image
  }
  // RViz markers (visualization_msgs/MarkerArray as ROS 2 defines it): per frame a DELETEALL, then per object
  // a sphere, a text with its id and speed, and for a moving object an arrow with two points.
  ASSERT_EQ(d.markers_by_stamp.size(), static_cast<size_t>(kFrames));
  for (const auto& [stamp, rows] : d.markers_by_stamp) {
    ASSERT_TRUE(d.objects_by_stamp.count(stamp)) << stamp;
    const auto& frame_objects = d.objects_by_stamp.at(stamp);
    ASSERT_FALSE(rows.empty());
    EXPECT_EQ(rows[0][4], "3");  // DELETEALL
    int spheres = 0, texts = 0, arrows = 0, moving = 0;
    for (const auto& o : frame_objects) moving += o[2] == "1";
    for (size_t i = 1; i < rows.size(); ++i) {
      const int type = std::stoi(rows[i][3]);
      spheres += type == 2, arrows += type == 0, texts += type == 9;
      if (type == 0) {
        EXPECT_EQ(rows[i][5], "2");
      }
      if (type == 9) {
        EXPECT_EQ(rows[i][6].back(), ':') << "the text starts with the id";
      }
    }
    EXPECT_EQ(spheres, static_cast<int>(frame_objects.size())) << stamp;
    EXPECT_EQ(texts, static_cast<int>(frame_objects.size())) << stamp;
    EXPECT_LE(arrows, moving) << stamp;
  }
  // The status, field by field: the last one counts the whole session.
  ASSERT_FALSE(d.status_rows.empty());
  const std::vector<std::string>& last = d.status_rows.back();
  EXPECT_EQ(last[3], "-");  // no vehicle namespace
  EXPECT_EQ(std::stoull(last[4]), 4u * kFrames);  // colour, depth, mask, odometry
  EXPECT_EQ(std::stoull(last[5]), static_cast<uint64_t>(kFrames));
  EXPECT_EQ(std::stoull(last[6]), static_cast<uint64_t>(kFrames));
  for (int i = 7; i <= 10; ++i) EXPECT_EQ(last[i], "0") << "field " << i;  // nothing dropped, rejected or lost
  EXPECT_GT(std::stod(last[11]), 0.0);  // latency
}

// The frames of `dataset` as a camera driver holds them: raw rgb8 colour, 32FC1 depth and 16UC1 mask files,
// and a line per frame for dslam_cyclone_camera_driver (the odometry as dslam publish sends it: the pose
// accumulated from the increments, the increment's sigmas per second since the previous frame).
std::string DriverFrames(const std::string& dataset, const std::string& dir) {
  const ImageDataset data(dataset, ImageDatasetOptions{});
  std::filesystem::create_directories(dir);
  const std::string list = dir + "/frames.txt";
  std::ofstream out(list);
  out << std::setprecision(17);
  SE3 T_odom_camera;
  int64_t previous_t_ns = 0;
  auto write = [&](const cv::Mat& m, const std::string& path) {
    const cv::Mat c = m.isContinuous() ? m : m.clone();
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(c.data), c.total() * c.elemSize());
  };
  for (int k = 0; k < data.size(); ++k) {
    const ImageFrame f = data.read(k);
    Vec6 sigma = Vec6::Constant(0.01);
    if (f.odometry) T_odom_camera = T_odom_camera * f.odometry->T_prev_curr, sigma = f.odometry->sigma;
    const double dt_s = k > 0 ? static_cast<double>(f.t_ns - previous_t_ns) * 1e-9 : 0.0;
    const Vec6 twist_sigma = dt_s > 0.0 ? Vec6(sigma / dt_s) : Vec6::Zero();
    previous_t_ns = f.t_ns;
    cv::Mat rgb, ids;
    cv::cvtColor(f.image, rgb, cv::COLOR_BGR2RGB);
    f.instance_ids.convertTo(ids, CV_16U);
    const std::string stem = dir + "/" + std::to_string(k);
    write(rgb, stem + "_rgb8.raw");
    write(f.depth_m, stem + "_32fc1.raw");
    write(ids, stem + "_16uc1.raw");
    const Vec3 t = T_odom_camera.translation();
    const auto q = T_odom_camera.rotation();
    out << f.t_ns << ' ' << f.image.rows << ' ' << f.image.cols << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' '
        << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w();
    for (int i = 0; i < 6; ++i) out << ' ' << twist_sigma[i];
    out << ' ' << stem << "_rgb8.raw " << stem << "_32fc1.raw " << stem << "_16uc1.raw\n";
  }
  return list;
}

// A ROS 2 camera driver on Cyclone DDS feeds serve as rclcpp would: sensor-data QoS (best effort, keep last 5),
// rgb8 colour, 32FC1 depth, 16UC1 mask, odometry, over UDP with shared memory off on the Fast DDS side (serve's
// shipped profile otherwise). Every frame is estimated, and the estimates (read back by the Cyclone listener)
// equal what the same frames give through serve's code as dslam publish feeds it, to 1e-9.
TEST(CycloneInterop, ACameraDriverOnCycloneDdsFeedsServeAndEveryFrameIsEstimatedExactly) {
  constexpr int kFrames = 12;
  const std::string dataset = test::RenderedCity("cyclone_city_12", kFrames, 1);
  ASSERT_FALSE(dataset.empty());
  const int domain = test::DomainFor(test::DdsTestSlot::kCycloneCameraDriver);
  const std::string profiles = test::WithoutSharedMemory(kProfiles, test::TempPath("cyclone_driver_udp.xml"));
  const std::string frames = DriverFrames(dataset, test::TempPath("cyclone_driver_frames"));
  test::Process serve(ServeArgs(domain, profiles, dataset, test::TempPath("cyclone_driver_out")),
                      test::TempPath("cyclone_driver_serve.log"));
  const std::string decoded_path = test::TempPath("cyclone_driver_decoded.txt");
  const auto listener = StartListener(domain, kFrames, decoded_path, test::TempPath("cyclone_driver_listener.log"));
  test::Process driver(DSLAM_CYCLONE_CAMERA_DRIVER, {std::to_string(domain), "rt/", frames, "2"},
                       test::TempPath("cyclone_driver.log"));
  ASSERT_EQ(driver.wait(120s), 0) << test::ReadFile(test::TempPath("cyclone_driver.log"));
  EXPECT_EQ(listener->wait(150s), 0) << test::ReadFile(test::TempPath("cyclone_driver_listener.log"));
  serve.signal(SIGTERM);
  ASSERT_EQ(serve.wait(60s), 0) << test::ReadFile(test::TempPath("cyclone_driver_serve.log"));

  const Decoded d = ReadDecoded(decoded_path);
  const std::vector<FrameEstimate> reference = test::ServeReference(dataset);
  ASSERT_EQ(reference.size(), static_cast<size_t>(kFrames));
  ASSERT_EQ(d.odometry.size(), reference.size());
  for (const FrameEstimate& e : reference) {
    ASSERT_TRUE(d.odometry.count(e.t_ns)) << e.t_ns;
    const std::vector<double>& got = d.odometry.at(e.t_ns);
    const Vec3 t = e.T_world_camera.translation();
    const auto q = e.T_world_camera.rotation();
    const std::vector<double> expected = {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
    for (int i = 0; i < 7; ++i) EXPECT_NEAR(got[i], expected[i], 1e-9) << e.t_ns << " field " << i;
    const auto& objects = d.objects_by_stamp.at(e.t_ns);
    ASSERT_EQ(objects.size(), e.object_motions.size()) << e.t_ns;
    for (size_t i = 0; i < objects.size(); ++i) {
      EXPECT_EQ(std::stoi(objects[i][1]), e.object_motions[i].object_id);
      EXPECT_EQ(objects[i][2] == "1", e.object_motions[i].is_dynamic);
      EXPECT_NEAR(std::stod(objects[i][3]), e.object_motions[i].speed_mps, 1e-9);
    }
  }
  ASSERT_FALSE(d.status_rows.empty());
  const std::vector<std::string>& last = d.status_rows.back();
  EXPECT_EQ(std::stoull(last[4]), 4u * kFrames);                      // every sample arrived
  EXPECT_EQ(std::stoull(last[6]), static_cast<uint64_t>(kFrames));  // every frame estimated
  for (int i = 7; i <= 10; ++i) EXPECT_EQ(last[i], "0") << "field " << i;
}

// The reverse of a camera driver: `dslam publish` feeds a ROS 2 node on Cyclone DDS that reads with the
// sensor-data QoS over UDP (shared memory off on the Fast DDS side), at 10 Hz, 1242x375 images. The node's
// receive buffer holds a frame's burst of fragments (CYCLONEDDS_URI, as a ROS 2 user sets it for images);
// no sample is lost.
TEST(CycloneInterop, PublishFeedsACycloneDdsReaderAtTenHertzWithoutLosingAFrame) {
  constexpr int kFrames = 20;
  const std::string dataset = test::RenderedCity("cyclone_city_20", kFrames, 2);
  ASSERT_FALSE(dataset.empty());
  const int domain = test::DomainFor(test::DdsTestSlot::kCycloneImageReader);
  const std::string profiles = test::WithoutSharedMemory(kProfiles, test::TempPath("cyclone_reader_udp.xml"));
  const std::string decoded_path = test::TempPath("cyclone_images.txt");
  setenv("CYCLONEDDS_URI",
         "<CycloneDDS><Domain><Internal><SocketReceiveBufferSize min=\"4MB\"/></Internal></Domain></CycloneDDS>", 1);
  test::Process reader(DSLAM_CYCLONE_IMAGE_READER,
                       {std::to_string(domain), "rt/", std::to_string(kFrames), "120", decoded_path},
                       test::TempPath("cyclone_reader.log"));
  unsetenv("CYCLONEDDS_URI");
  std::this_thread::sleep_for(3s);
  test::Process publish({"publish", "--domain", std::to_string(domain), "--profiles", profiles, "--dataset", dataset,
                         "--rate", "10", "--wait", "60"},
                        test::TempPath("cyclone_reader_publish.log"));
  ASSERT_EQ(publish.wait(120s), 0) << test::ReadFile(test::TempPath("cyclone_reader_publish.log"));
  EXPECT_EQ(reader.wait(60s), 0) << test::ReadFile(test::TempPath("cyclone_reader.log"));

  std::map<std::string, std::set<int64_t>> stamps;  // topic -> stamps received
  std::ifstream in(decoded_path);
  for (std::string line; std::getline(in, line);) {
    std::istringstream f(line);
    std::string kind, topic;
    long long sec = 0, nanosec = 0;
    f >> kind;
    if (kind == "image") {
      unsigned height = 0, width = 0, step = 0, bytes = 0;
      std::string encoding;
      f >> topic >> sec >> nanosec >> height >> width >> encoding >> step >> bytes;
      EXPECT_EQ(height, 375u) << line;
      EXPECT_EQ(width, 1242u) << line;
      EXPECT_EQ(static_cast<size_t>(bytes), static_cast<size_t>(step) * height) << line;
      const std::string expected = topic == "camera/color/image_raw"   ? "bgr8"
                                   : topic == "camera/depth/image_raw" ? "32FC1"
                                                                       : "16UC1";
      EXPECT_EQ(encoding, expected) << line;
    } else {
      topic = "odom";
      f >> sec >> nanosec;
    }
    stamps[topic].insert(sec * 1'000'000'000LL + nanosec);
  }
  ASSERT_EQ(stamps.size(), 4u);
  for (const auto& [topic, received] : stamps) EXPECT_EQ(received.size(), static_cast<size_t>(kFrames)) << topic;
}

}  // namespace
}  // namespace dslam
