// Every reader of dataset inputs (KITTI and VDO-SLAM text files, calibration, odometry, oxts, dense maps,
// LiDAR scans, images, the YAML configuration, TUM trajectories) fed damaged copies of a good file: each
// one is read or rejected with a std::runtime_error / std::invalid_argument naming the file, never a
// crash, a hang or another exception. Seeded and small: it runs in a few seconds.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>


#include "data/dense_maps.h"
#include "data/image_codec.h"
#include "data/image_dataset.h"
#include "data/kitti_tracking.h"
#include "data/odometry_file.h"
#include "data/velodyne.h"
#include "output/trajectory_io.h"
#include "pipeline/config_yaml.h"
#include "support/child_process.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

std::string Binary(const void* data, size_t bytes) { return std::string(static_cast<const char*>(data), bytes); }

// One damage of `good`, chosen by `trial`: truncation, a changed byte, bytes lost, a bogus line, a
// duplicated line, numbers out of any range.
std::string Damage(const std::string& good, int trial, std::mt19937& rng) {
  std::string bad = good;
  if (bad.empty()) return bad;
  const size_t at = std::uniform_int_distribution<size_t>(0, bad.size() - 1)(rng);
  switch (trial % 8) {
    case 0: bad.resize(at); break;
    case 1: bad[at] = static_cast<char>(rng() % 256); break;
    case 2: bad.erase(at, std::min<size_t>(6, bad.size() - at)); break;
    case 3: bad.insert(at, "\n1e999 nan -1 inf 99999999999999999999\n"); break;
    case 4: {
      const size_t line_end = bad.find('\n');
      if (line_end != std::string::npos) bad.insert(0, bad.substr(0, line_end + 1));  // first line twice
      break;
    }
    case 5: bad.insert(at, " -1e300 "); break;
    case 6: bad.insert(at, std::string(1, '\0')); break;
    case 7: bad = bad.substr(at) + bad.substr(0, at); break;  // rotated
  }
  return bad;
}

void ExpectNamesFile(const std::exception& e, const std::string& path, const std::string& name, bool required) {
  if (!required) return;
  EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << name << ": " << e.what();
}

// Runs `read` on damaged copies of `good` written to `path`; anything but success or a named error fails.
void Fuzz(const std::string& name, const std::string& good, const std::function<void(const std::string&)>& read,
          bool error_names_file = true, int trials = 64) {
  std::mt19937 rng(11);
  const std::string path = test::TempPath("fuzz_" + name);
  {
    std::ofstream(path, std::ios::binary) << good;
    EXPECT_NO_THROW(read(path)) << name << ": the good file is rejected";
  }
  for (int trial = 0; trial < trials; ++trial) {
    const std::string bad = Damage(good, trial, rng);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bad;
    try {
      read(path);
    } catch (const std::runtime_error& e) {
      ExpectNamesFile(e, path, name, error_names_file);
    } catch (const std::invalid_argument& e) {
      ExpectNamesFile(e, path, name, error_names_file);
    } catch (const std::exception& e) {
      ADD_FAILURE() << name << " trial " << trial << ": unexpected " << typeid(e).name() << ": " << e.what();
    }
  }
  fs::remove(path);
}

TEST(ReaderFuzz, KittiAndVdoTextFiles) {
  Fuzz("labels",
       "0 1 Car 0 0 -1.5 10 10 50 50 1.5 1.6 3.9 2.0 1.7 15.0 -1.57\n"
       "0 -1 DontCare -1 -1 -10 219 164 340 189 -1000 -1000 -1000 -10 -1 -1 -1\n"
       "1 1 Car 0 0 -1.5 10 10 50 50 1.5 1.6 3.9 2.1 1.7 15.5 -1.57\n",
       [](const std::string& p) { ReadKittiLabels(p); });
  Fuzz("pose_gt",
       "0 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n1 1 0 0 0.5 0 1 0 0 0 0 1 1.0 0 0 0 1\n",
       [](const std::string& p) { ReadPoseGt(p); });
  Fuzz("object_pose", "0 1 1 2 3 4 1.0 1.6 10.0 0.1\n1 1 1 2 3 4 1.1 1.6 10.5 0.1\n",
       [](const std::string& p) { ReadObjectPoses(p); });
  Fuzz("times", "0.0\n0.1\n0.2\n", [](const std::string& p) { ReadTimes(p); });
  Fuzz("categories", "1 VEHICLE\n2 PEDESTRIAN\n", [](const std::string& p) { ReadObjectCategories(p); });
  Fuzz("calib",
       "P0: 721 0 609 0 0 721 172 0 0 0 1 0\nP1: 721 0 609 -387 0 721 172 0 0 0 1 0\n"
       "P2: 721 0 609 44 0 721 172 0.2 0 0 1 0.003\nP3: 721 0 609 -339 0 721 172 2.2 0 0 1 0.003\n"
       "R0_rect: 1 0 0 0 1 0 0 0 1\nTr_velo_to_cam: 0 -1 0 0 0 0 -1 -0.08 1 0 0 -0.27\n"
       "Tr_imu_to_velo: 1 0 0 -0.8 0 1 0 0.3 0 0 1 -0.8\n",
       [](const std::string& p) { ReadKittiCalibration(p); });
  std::string oxts;
  for (int k = 0; k < 3; ++k) {
    oxts += std::to_string(49.01 + 1e-5 * k) + " 8.43 112.9 0.02 0.01 -0.5";
    for (int i = 6; i < 30; ++i) oxts += " 0.1";
    oxts += "\n";
  }
  Fuzz("oxts", oxts, [](const std::string& p) { ReadOxts(p); });
}

TEST(ReaderFuzz, OdometryTrajectoryAndConfiguration) {
  const std::string odometry_path = test::TempPath("fuzz_odometry_good.txt");
  std::map<int, OdometryMeasurement> increments;
  increments[1].T_prev_curr = SE3(Eigen::Quaterniond::Identity(), Vec3(0, 0, 1));
  increments[2].T_prev_curr = SE3(Eigen::Quaterniond::Identity(), Vec3(0.1, 0, 1));
  WriteOdometryFile(odometry_path, increments);
  Fuzz("odometry", test::ReadFile(odometry_path), [](const std::string& p) { ReadOdometryFile(p); });
  Fuzz("tum", "0.0 0 0 0 0 0 0 1\n0.1 0 0 1 0 0 0 1\n0.2 0.1 0 2 0 0 0.01 0.99995\n",
       [](const std::string& p) { ReadTumTrajectory(p); });
  // The YAML parser names the source it is given.
  Fuzz("config", test::ReadFile(std::string(DSLAM_SOURCE_DIR) + "/config/default.yaml"),
       [](const std::string& p) { ParseRunConfig(test::ReadFile(p), p); });
}

TEST(ReaderFuzz, DenseMapsAndLidarScans) {
  Fuzz("semantic", "0 0 5 5\n0 0 5 5\n0 7 7 0\n", [](const std::string& p) { ReadSemanticTxt(p); });
  std::string flo;
  const float magic = 202021.25f;
  const int32_t w = 3, h = 2;
  flo += Binary(&magic, 4) + Binary(&w, 4) + Binary(&h, 4);
  for (int i = 0; i < w * h * 2; ++i) {
    const float v = 0.5f * static_cast<float>(i);
    flo += Binary(&v, 4);
  }
  Fuzz("flo", flo, [](const std::string& p) { ReadFlo(p); });
  std::string scan;
  for (int i = 0; i < 4; ++i) {
    const float point[4] = {8.0f + static_cast<float>(i), 0.5f, -1.0f, 0.3f};
    scan += Binary(point, sizeof point);
  }
  Fuzz("velodyne", scan, [](const std::string& p) { ReadVelodyneScan(p); });
}

TEST(ReaderFuzz, DamagedImagesOfADataset) {
  // A two-frame VDO-layout dataset whose image, depth and mask PNGs are damaged in turn.
  const std::string dir = test::TempDir("fuzz_images");
  for (const char* sub : {"image_0", "depth", "mask"}) fs::create_directories(dir + "/" + sub);
  for (int k = 0; k < 2; ++k) {
    char name[16];
    std::snprintf(name, sizeof name, "%06d.png", k);
    dslam::WritePngFile(dir + "/image_0/" + name, cv::Mat(24, 32, CV_8UC3, cv::Scalar(10 * k, 20, 30)));
    dslam::WritePngFile(dir + "/depth/" + name, cv::Mat(24, 32, CV_16UC1, cv::Scalar(2000)));
    dslam::WritePngFile(dir + "/mask/" + name, cv::Mat(24, 32, CV_16UC1, cv::Scalar(0)));
  }
  std::ofstream(dir + "/calib.txt") << "P0: 20 0 16 0 0 20 12 0 0 0 1 0\nP2: 20 0 16 0 0 20 12 0 0 0 1 0\n"
                                       "R0_rect: 1 0 0 0 1 0 0 0 1\n";
  for (const char* sub : {"image_0", "depth", "mask"}) {
    const std::string path = dir + "/" + sub + "/000001.png";
    const std::string good = test::ReadFile(path);
    Fuzz(std::string("png_") + sub, good,
         [&](const std::string& damaged) {
           fs::copy_file(damaged, path, fs::copy_options::overwrite_existing);
           const ImageDataset data(dir, {});
           data.read(1);
         },
         /*error_names_file=*/false, 24);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << good;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dslam
