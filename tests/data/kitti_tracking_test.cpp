#include "data/kitti_tracking.h"

#include <gtest/gtest.h>

#include "support/temp_paths.h"

#include <filesystem>
#include <fstream>

#include "data/kitti_dataset.h"

namespace dslam {
namespace {

using test::TempDir;
using test::TempPath;

namespace fs = std::filesystem;
const fs::path kKitti = fs::path(DSLAM_SHARED_DATA_DIR) / "kitti_tracking";

#define REQUIRE_SHARED_DATA()                                                            \
  if (!fs::exists(kKitti / "label_02" / "0000.txt")) GTEST_SKIP() << "shared data absent: " << kKitti


void ExpectErrorAt(const std::function<void()>& read, const std::string& where) {
  try {
    read();
    FAIL() << "expected an error at " << where;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
  }
}

TEST(KittiCalibration, ReadsSequence0000) {
  REQUIRE_SHARED_DATA();
  const KittiCalibration c = ReadKittiCalibration((kKitti / "calib" / "0000.txt").string());
  EXPECT_DOUBLE_EQ(c.fx(), 721.5377);
  EXPECT_DOUBLE_EQ(c.cx(), 609.5593);
  EXPECT_DOUBLE_EQ(c.cy(), 172.854);
  // Stereo baseline from P2 / P3 (metres): about 0.54 m.
  const double baseline = (c.P[2](0, 3) - c.P[3](0, 3)) / c.fx();
  EXPECT_NEAR(baseline, 0.532, 0.01);
  EXPECT_NEAR((c.R_rect * c.R_rect.transpose() - Mat3::Identity()).norm(), 0.0, 1e-5);
}

TEST(KittiLabels, ReadsSequence0000AndSkipsDontCare) {
  REQUIRE_SHARED_DATA();
  const auto labels = ReadKittiLabels((kKitti / "label_02" / "0000.txt").string());
  ASSERT_FALSE(labels.empty());
  for (const auto& l : labels) {
    EXPECT_NE(l.type, "DontCare");
    EXPECT_GE(l.track_id, 0);
  }
  // First row after the DontCare ones: the Van of track 0 (see the shared data's README).
  EXPECT_EQ(labels.front().type, "Van");
  EXPECT_NEAR(labels.front().bottom_centre_camera.z(), 13.410495, 1e-9);
}

TEST(KittiLabels, MalformedInputNamesFileAndLine) {
  const fs::path dir = fs::path(TempDir("labels"));
  const std::string good = "0 1 Car 0 0 -1.5 10 10 50 50 1.5 1.6 3.9 2.0 1.7 15.0 -1.57";
  const std::string path = (dir / "l.txt").string();
  std::ofstream(path) << good << "\n0 1 Car 0 0 -1.5 10 10 50 50 1.5 1.6\n";
  ExpectErrorAt([&] { ReadKittiLabels(path); }, path + ":2: expected 17-18 fields");
  const std::string other = "0 2 Car 0 0 -1.5 10 10 50 50 1.5 1.6 3.9 2.0 1.7 15.0 -1.57";
  std::ofstream(path) << good << "\n" << other << "\n0 1 Car 0 0 -1.5 10 10 50 50 1.5 abc 3.9 2.0 1.7 15.0 -1.57\n";
  ExpectErrorAt([&] { ReadKittiLabels(path); }, path + ":3: label field 12 'abc' is not a finite number");
  std::ofstream(path) << "0 1 Car 0 0 -1.5 10 10 50 50 1.5 -1.6 3.9 2.0 1.7 15.0 -1.57\n";
  ExpectErrorAt([&] { ReadKittiLabels(path); }, path + ":1: object size h w l must be positive");
  std::ofstream(path) << "0 1 Car 0 0 -1.5 10 10 50 50 1.5 nan 3.9 2.0 1.7 15.0 -1.57\n";
  ExpectErrorAt([&] { ReadKittiLabels(path); }, path + ":1:");
  ExpectErrorAt([&] { ReadKittiLabels((dir / "missing.txt").string()); }, "cannot open");
  // Stamps that would overflow int64 nanoseconds into negative ones.
  const std::string times = (dir / "times.txt").string();
  std::ofstream(times) << "0.0\n1e10\n";
  ExpectErrorAt([&] { ReadTimes(times); }, times + ":2: timestamp 1e10 s is outside [0, 9.2e9) s");
  std::ofstream(times) << "-1\n";
  ExpectErrorAt([&] { ReadTimes(times); }, times + ":1:");
  std::ofstream(times) << "0.0\n0.1\n";
  EXPECT_EQ(ReadTimes(times).size(), 2u);
  // A track labelled twice in a frame would silently replace its first box; frames must not go back.
  std::ofstream(path) << good << "\n" << other << "\n" << good << "\n";
  ExpectErrorAt([&] { ReadKittiLabels(path); }, path + ":3: track 1 labelled twice in frame 0 (first on line 1)");
  std::ofstream(path) << "1 1 Car 0 0 -1.5 10 10 50 50 1.5 1.6 3.9 2.0 1.7 15.0 -1.57\n" << good << "\n";
  ExpectErrorAt([&] { ReadKittiLabels(path); }, path + ":2: frame 0 out of order: after frame 1");
  // The same track in consecutive frames is what labels are.
  std::ofstream(path) << good << "\n1 1 Car 0 0 -1.5 10 10 50 50 1.5 1.6 3.9 2.0 1.7 15.0 -1.57\n";
  EXPECT_EQ(ReadKittiLabels(path).size(), 2u);
  fs::remove_all(dir);
}

TEST(VdoFiles, ReadSequence0000) {
  REQUIRE_SHARED_DATA();
  const fs::path gt = kKitti / "gt" / "0000";
  const auto poses = ReadPoseGt((gt / "pose_gt.txt").string());
  EXPECT_EQ(poses.size(), 154u);
  EXPECT_TRUE(poses.front().isApprox(SE3::Identity(), 1e-9));
  double path_m = 0.0;
  for (size_t k = 1; k < poses.size(); ++k) path_m += (poses[k].translation() - poses[k - 1].translation()).norm();
  EXPECT_NEAR(path_m, 69.0, 3.0);  // the shared data README's figure
  const auto objects = ReadObjectPoses((gt / "object_pose.txt").string());
  ASSERT_FALSE(objects.empty());
  EXPECT_EQ(objects.front().object_id, 1);
  EXPECT_NEAR(objects.front().rotation_y, -2.115488, 1e-6);
  EXPECT_EQ(ReadTimes((gt / "times.txt").string()).size(), 154u);
  EXPECT_EQ(ReadObjectCategories((gt / "object_category.txt").string()).at(1), "VEHICLE");
}

TEST(VdoFiles, MalformedInputNamesFileAndLine) {
  const fs::path dir = fs::path(TempDir("vdo"));
  const std::string pose = (dir / "pose_gt.txt").string();
  std::ofstream(pose) << "0 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n2 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n";
  ExpectErrorAt([&] { ReadPoseGt(pose); }, pose + ":2: frame 2 out of order");
  std::ofstream(pose) << "0 2 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n";
  ExpectErrorAt([&] { ReadPoseGt(pose); }, pose + ":1: the rotation block is not a rotation");
  // A 1e300 m position gave NaN metrics and exit 0.
  std::ofstream(pose) << "0 1 0 0 1e300 0 1 0 0 0 0 1 0 0 0 0 1\n";
  ExpectErrorAt([&] { ReadPoseGt(pose); }, pose + ":1: the position is more than 1e7 m from the origin");
  const std::string times = (dir / "times.txt").string();
  std::ofstream(times) << "0\n0.1\n0.05\n";
  ExpectErrorAt([&] { ReadTimes(times); }, times + ":3: time goes backwards");
  std::ofstream(times) << "0\n0.1\n0.1\n";  // two frames at one instant: a speed over zero seconds
  ExpectErrorAt([&] { ReadTimes(times); }, times + ":3: timestamp 0.1 s repeats the previous line's");
  const std::string obj = (dir / "object_pose.txt").string();
  std::ofstream(obj) << "0\t1\t1\t2\t3\t4\t1.0\t1.6\n";
  ExpectErrorAt([&] { ReadObjectPoses(obj); }, obj + ":1: expected 10 fields, found 8");
  std::ofstream(obj) << "0 1 1 2 3 4 1.0 1.6 1e300 0.1\n";
  ExpectErrorAt([&] { ReadObjectPoses(obj); }, obj + ":1: the position is more than 1e7 m from the camera");
  // An object listed twice in a frame was taken silently (its second pose replaced the first).
  std::ofstream(obj) << "0 1 1 2 3 4 1.0 1.6 10 0.1\n0 2 1 2 3 4 2.0 1.6 10 0.1\n0 1 1 2 3 4 1.5 1.6 10 0.1\n";
  ExpectErrorAt([&] { ReadObjectPoses(obj); }, obj + ":3: object 1 listed twice in frame 0 (first on line 1)");
  fs::remove_all(dir);
}

// Inverse of KITTI's Mercator projection, to write oxts records for a known IMU trajectory.
OxtsRecord ToOxts(const SE3& T_world_imu, double lat0_deg) {
  constexpr double er = 6378137.0;
  const double scale = std::cos(lat0_deg * M_PI / 180.0);
  OxtsRecord r;
  const Vec3 t = T_world_imu.translation();
  r.lon_deg = t.x() * 180.0 / (M_PI * er * scale);
  r.lat_deg = std::atan(std::exp(t.y() / (scale * er))) * 360.0 / M_PI - 90.0;
  r.alt_m = t.z();
  const Vec3 ypr = T_world_imu.rotationMatrix().eulerAngles(2, 1, 0);
  r.yaw = ypr[0], r.pitch = ypr[1], r.roll = ypr[2];
  return r;
}

TEST(Oxts, CameraPosesFollowTheCalibrationChain) {
  const double lat0 = 49.0;
  constexpr double er = 6378137.0;
  const double y0 = std::cos(lat0 * M_PI / 180.0) * er * std::log(std::tan((90.0 + lat0) * M_PI / 360.0));
  std::vector<SE3> imu;
  for (int k = 0; k < 5; ++k)
    imu.push_back(SE3(Eigen::AngleAxisd(0.05 * k + 0.3, Vec3::UnitZ()).toRotationMatrix(), Vec3(1000.0 + k, y0 + 0.5 * k, 110.0)));
  const fs::path dir = fs::path(TempDir("oxts"));
  const std::string path = (dir / "0001.txt").string();
  {
    std::ofstream out(path);
    out.precision(15);
    for (const auto& T : imu) {
      const OxtsRecord r = ToOxts(T, lat0);
      out << r.lat_deg << ' ' << r.lon_deg << ' ' << r.alt_m << ' ' << r.roll << ' ' << r.pitch << ' ' << r.yaw;
      for (int i = 6; i < 30; ++i) out << " 0";
      out << '\n';
    }
  }
  KittiCalibration calib;
  calib.P[2] << 700, 0, 600, 0, 0, 700, 180, 0, 0, 0, 1, 0;
  calib.T_cam_velo.topLeftCorner<3, 3>() << 0, -1, 0, 0, 0, -1, 1, 0, 0;  // velodyne x forward -> camera z
  calib.T_cam_velo.topRightCorner<3, 1>() << 0.0, -0.08, -0.27;
  calib.T_velo_imu.topRightCorner<3, 1>() << -0.8, 0.3, -0.8;
  const auto poses = CameraPosesFromOxts(ReadOxts(path), calib);
  ASSERT_EQ(poses.size(), 5u);
  const SE3 C = SE3::FromMatrix(calib.T_rect_imu());
  EXPECT_TRUE(poses[0].isApprox(SE3::Identity(), 1e-6));  // metres from the Earth's equator: 1e-9 relative
  for (int k = 1; k < 5; ++k) EXPECT_TRUE(poses[k].isApprox(C * imu[0].inverse() * imu[k] * C.inverse(), 1e-6)) << k;

  std::ofstream(path) << "49.0 8.4 110\n";
  ExpectErrorAt([&] { ReadOxts(path); }, path + ":1: expected 30 fields, found 3");
  fs::remove_all(dir);
}

TEST(KittiDataset, LoadsBothLayoutsOfSequence0000) {
  REQUIRE_SHARED_DATA();
  // The shared folder holds KITTI's layout (labels, calib) with the VDO files under gt/.
  const auto full = LoadKittiGroundTruth(kKitti.string(), "0000");
  EXPECT_EQ(full.T_world_camera.size(), 154u);
  ASSERT_TRUE(full.calibration);
  ASSERT_TRUE(full.objects.count(1));
  EXPECT_EQ(full.objects.at(1).type, "Van");
  EXPECT_TRUE(full.objects.at(1).size_from_labels);
  EXPECT_NEAR(full.objects.at(1).l, 4.433886, 1e-9);

  // VDO-SLAM layout alone: a folder with only pose_gt.txt, object_pose.txt, times.txt, object_category.txt.
  const fs::path vdo = fs::path(TempDir("vdo_layout"));
  for (const char* f : {"pose_gt.txt", "object_pose.txt", "times.txt", "object_category.txt"})
    fs::copy_file(kKitti / "gt" / "0000" / f, vdo / f, fs::copy_options::overwrite_existing);
  const auto only_vdo = LoadKittiGroundTruth(vdo.string(), "0000");
  EXPECT_EQ(only_vdo.T_world_camera.size(), 154u);
  EXPECT_EQ(only_vdo.objects.size(), full.objects.size());
  EXPECT_FALSE(only_vdo.objects.at(1).size_from_labels);
  // Same object poses either way.
  const auto& a = full.objects.at(1).T_camera_object;
  const auto& b = only_vdo.objects.at(1).T_camera_object;
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(a.begin()->second.isApprox(b.begin()->second, 1e-5));
  fs::remove_all(vdo);
}

TEST(KittiDataset, MissingFilesAreClearErrors) {
  const fs::path dir = fs::path(TempDir("empty"));
  ExpectErrorAt([&] { LoadKittiGroundTruth(dir.string(), "0042"); }, "no camera poses for sequence 0042");
  ExpectErrorAt([&] { LoadKittiGroundTruth((dir / "nope").string(), "0042"); }, "does not exist");
  std::ofstream(dir / "pose_gt.txt") << "0 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n";
  ExpectErrorAt([&] { LoadKittiGroundTruth(dir.string(), "0042"); }, "no object ground truth");
  fs::create_directories(dir / "label_02");
  std::ofstream(dir / "label_02" / "0042.txt") << "3 0 Car 0 0 -1.5 10 10 50 50 1.5 1.6 3.9 2.0 1.7 15.0 -1.57\n";
  ExpectErrorAt([&] { LoadKittiGroundTruth(dir.string(), "0042"); }, "frame 3 beyond the 1 camera poses");
  fs::remove_all(dir);
}

// A car 10 m ahead, then 30 m ahead (beyond a 22 m range), labelled in frames 0-3; its mask is too small in frame 1.
TEST(KittiGroundTruth, AnObjectIsObservedWhereItIsInRangeAndSeenAndFrameByFrameAsAtOnce) {
  KittiGroundTruthSequence kitti;
  KittiObjectTrack car;
  car.object_id = 4;
  car.h = 1.5, car.w = 1.6, car.l = 4.0;
  for (int k = 0; k < 4; ++k) {
    kitti.T_world_camera.push_back(SE3(Mat3::Identity(), Vec3(0.0, 0.0, k)));
    car.T_camera_object[k] = SE3(Mat3::Identity(), Vec3(0.0, 0.0, k < 2 ? 10.0 : 30.0));
  }
  kitti.objects[4] = car;
  const auto visible = [](int k, int id) { return id == 4 && k != 1; };
  const GroundTruth at_once = ToGroundTruth(kitti, 4, 22.0, visible);
  ASSERT_EQ(at_once.objects.count(4), 1u);
  EXPECT_EQ(at_once.objects.at(4).observed_frames, (std::set<int>{0}));
  EXPECT_EQ(at_once.objects.at(4).L_world_object.size(), 4u);

  GroundTruth by_frame = ToUnobservedGroundTruth(kitti, 4);
  EXPECT_TRUE(by_frame.objects.at(4).observed_frames.empty());
  for (int k = 0; k < 4; ++k) ObserveFrame(k, 22.0, visible, &by_frame);
  EXPECT_EQ(by_frame.objects.at(4).observed_frames, at_once.objects.at(4).observed_frames);
  EXPECT_THROW(ToUnobservedGroundTruth(kitti, 5), std::invalid_argument);  // more frames than poses
}

}  // namespace
}  // namespace dslam
