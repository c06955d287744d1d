#include "data/image_dataset.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <opencv2/imgproc.hpp>

#include "data/image_codec.h"
#include "data/odometry_file.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

constexpr int kW = 64, kH = 48;

std::string Name(int k, const char* ext) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%06d.%s", k, ext);
  return buf;
}

void WriteCalib(const std::string& path, double baseline_px = 0.0) {
  std::ofstream calib(path);
  for (int i = 0; i < 4; ++i)
    calib << 'P' << i << ": 50 0 32 " << (i == 3 ? -baseline_px : 0.0) << " 0 50 24 0 0 0 1 0\n";
  calib << "R0_rect: 1 0 0 0 1 0 0 0 1\nTr_velo_to_cam: 0 -1 0 0 0 0 -1 0 1 0 0 0\n";
}

// A three-frame VDO-layout sequence: grey images, depth k+1 metres, a 10x10 mask with id 5.
std::string MakeVdoDataset(const std::string& name) {
  const std::string dir = test::TempDir(name);
  for (const char* sub : {"image_0", "depth", "mask"}) fs::create_directories(dir + "/" + sub);
  for (int k = 0; k < 3; ++k) {
    dslam::WritePngFile(dir + "/image_0/" + Name(k, "png"), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(10 * k, 20, 30)));
    dslam::WritePngFile(dir + "/depth/" + Name(k, "png"), cv::Mat(kH, kW, CV_16UC1, cv::Scalar(1000 * (k + 1))));
    cv::Mat mask(kH, kW, CV_16UC1, cv::Scalar(0));
    mask(cv::Rect(5, 5, 10, 10)).setTo(5);
    dslam::WritePngFile(dir + "/mask/" + Name(k, "png"), mask);
  }
  WriteCalib(dir + "/calib.txt");
  std::map<int, OdometryMeasurement> odometry;
  odometry[1].T_prev_curr = SE3(Eigen::Quaterniond::Identity(), Vec3(0, 0, 1));
  odometry[2].T_prev_curr = SE3(Eigen::Quaterniond::Identity(), Vec3(0, 0, 2));
  WriteOdometryFile(dir + "/odometry.txt", odometry);
  std::ofstream(dir + "/times.txt") << "0.0\n0.1\n0.2\n";
  return dir;
}

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(ImageDataset, ReadsTheVdoLayoutFrameByFrame) {
  const std::string dir = MakeVdoDataset("vdo_ok");
  const ImageDataset data(dir, ImageDatasetOptions{});
  EXPECT_EQ(data.layout(), "vdo");
  ASSERT_EQ(data.size(), 3);
  EXPECT_EQ(data.camera().width, kW);
  EXPECT_DOUBLE_EQ(data.camera().fx, 50.0);
  EXPECT_TRUE(data.hasMasks());
  EXPECT_TRUE(data.hasOdometry());
  EXPECT_FALSE(data.groundTruth());
  const ImageFrame f = data.read(2);
  EXPECT_EQ(f.frame_index, 2);
  EXPECT_EQ(f.t_ns, 200'000'000);
  EXPECT_FLOAT_EQ(f.depth_m.at<float>(10, 10), 3.0f);
  EXPECT_EQ(f.instance_ids.at<uint16_t>(7, 7), 5);
  EXPECT_EQ(f.instance_ids.at<uint16_t>(30, 30), 0);
  ASSERT_TRUE(f.odometry);
  EXPECT_DOUBLE_EQ(f.odometry->T_prev_curr.translation().z(), 2.0);
  EXPECT_FALSE(data.read(0).odometry);
}

TEST(ImageDataset, NamesTheMissingCorruptOrMisfitFile) {
  const std::string dir = MakeVdoDataset("vdo_bad");
  fs::remove(dir + "/depth/" + Name(1, "png"));
  EXPECT_NE(ErrorOf([&] { ImageDataset(dir, {}); }).find("missing " + dir + "/depth/000001.png"), std::string::npos);

  const std::string dir2 = MakeVdoDataset("vdo_corrupt");
  std::ofstream(dir2 + "/image_0/" + Name(1, "png")) << "not a png";
  const ImageDataset data2(dir2, {});
  EXPECT_NE(ErrorOf([&] { data2.read(1); }).find("cannot read image " + dir2 + "/image_0/000001.png"),
            std::string::npos);
  dslam::WritePngFile(dir2 + "/depth/" + Name(2, "png"), cv::Mat(10, 10, CV_16UC1, cv::Scalar(1)));
  EXPECT_NE(ErrorOf([&] { data2.read(2); }).find("depth is 10x10 but the image is 64x48"), std::string::npos);
  dslam::WritePngFile(dir2 + "/depth/" + Name(0, "png"), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(1)));
  EXPECT_NE(ErrorOf([&] { data2.read(0); }).find("depth PNG must be 16-bit"), std::string::npos);

  // The first image gives the camera's size from its header; one that is no image, or cut short, is named
  // when the dataset opens.
  const std::string dir_first = MakeVdoDataset("vdo_first");
  std::ofstream(dir_first + "/image_0/" + Name(0, "png")) << "not a png";
  EXPECT_NE(ErrorOf([&] { ImageDataset(dir_first, {}); }).find("cannot read image " + dir_first + "/image_0/000000.png"),
            std::string::npos);
  std::vector<uint8_t> cut = EncodePng(cv::Mat(kH, kW, CV_8UC3, cv::Scalar(1, 2, 3)));
  cut.resize(cut.size() - 5);
  std::ofstream(dir_first + "/image_0/" + Name(0, "png"), std::ios::binary)
      .write(reinterpret_cast<const char*>(cut.data()), static_cast<std::streamsize>(cut.size()));
  EXPECT_NE(ErrorOf([&] { ImageDataset(dir_first, {}); }).find("000000.png: PNG cut off"), std::string::npos);

  const std::string dir3 = MakeVdoDataset("vdo_odometry");
  std::ofstream(dir3 + "/odometry.txt") << "1 0 0 nan 0 0 0 1 0.1 0.1 0.1 0.01 0.01 0.01\n";
  EXPECT_NE(ErrorOf([&] { ImageDataset(dir3, {}); }).find("odometry.txt:1: tz 'nan'"), std::string::npos);

  ImageDatasetOptions bad;
  bad.depth_encoding = "inverse_depth";
  EXPECT_NE(ErrorOf([&] { ImageDataset(dir3, bad); }).find("unknown depth encoding 'inverse_depth'"), std::string::npos);
  EXPECT_NE(ErrorOf([&] { ImageDataset(dir + "/nowhere", {}); }).find("does not exist"), std::string::npos);
  EXPECT_NE(ErrorOf([&] { ImageDataset(test::TempDir("empty_dataset"), {}); }).find("not an image dataset"),
            std::string::npos);
}

TEST(ImageDataset, SpeedsAreMeasuredAtTheDatasetsOwnRateUnlessItsTimesAreOverridden) {
  const std::string dir = MakeVdoDataset("vdo_rate");
  EXPECT_DOUBLE_EQ(ImageDataset(dir, {}).frameRateHz(), 10.0);  // times.txt: 0.1 s steps
  std::ofstream(dir + "/times.txt") << "0.0\n0.05\n0.1\n";     // a 20 Hz recording (or VDO-SLAM's KITTI times)
  const ImageDataset own(dir, {});
  EXPECT_NEAR(own.frameRateHz(), 20.0, 1e-9);
  EXPECT_EQ(own.frameRateSource(), "times.txt");
  EXPECT_TRUE(own.warnings().empty());
  ImageDatasetOptions overridden;
  overridden.override_times = true;  // the times are known wrong: frame k at k / frame_rate_hz
  const ImageDataset fixed(dir, overridden);
  EXPECT_DOUBLE_EQ(fixed.frameRateHz(), 10.0);
  EXPECT_EQ(fixed.stampNs(2), 200'000'000);
  EXPECT_EQ(fixed.frameRateSource(), "dataset.frame_rate_hz (override_times)");

  // A step far from the others is possible (a dropped frame) and said, naming the file and line.
  std::ofstream(dir + "/times.txt") << "0.0\n0.1\n0.3\n";
  const ImageDataset uneven(dir, {});
  ASSERT_EQ(uneven.warnings().size(), 1u);
  EXPECT_NE(uneven.warnings()[0].find("times.txt:3: a step of 0.2"), std::string::npos) << uneven.warnings()[0];
  // Times in milliseconds give no camera's rate: refused.
  std::ofstream(dir + "/times.txt") << "0\n100\n200\n";
  EXPECT_NE(ErrorOf([&] { ImageDataset(dir, {}); }).find("no camera's frame rate"), std::string::npos);
}

TEST(ImageDataset, ACalibrationInNormalisedUnitsIsRefused) {
  // fx = 0.78 for 64 px wide images (50 px in pixels): it parses, and every depth and motion would be wrong.
  const std::string dir = MakeVdoDataset("vdo_normalised");
  {
    std::ofstream calib(dir + "/calib.txt");
    for (int i = 0; i < 4; ++i) calib << 'P' << i << ": 0.78 0 0.5 0 0 0.78 0.5 0 0 0 1 0\n";
    calib << "R0_rect: 1 0 0 0 1 0 0 0 1\nTr_velo_to_cam: 0 -1 0 0 0 0 -1 0 1 0 0 0\n";
  }
  const std::string error = ErrorOf([&] { ImageDataset(dir, {}); });
  EXPECT_NE(error.find("calibration focal length 0.78"), std::string::npos) << error;
  EXPECT_NE(error.find("normalised units"), std::string::npos) << error;
  EXPECT_NO_THROW(ImageDataset(MakeVdoDataset("vdo_pixels"), {}));  // 50 px for 64 px: a 65 degree view
}

TEST(ImageDataset, AFrameMissingInTheMiddleIsAnErrorNamingItNotAShiftOfEveryLaterFrame) {
  // Removing frame 1's files used to pair image 000002.png with frame 1's time, odometry and ground truth.
  const std::string dir = MakeVdoDataset("vdo_gap");
  for (const char* sub : {"image_0", "depth", "mask"}) fs::remove(dir + "/" + sub + "/" + Name(1, "png"));
  const std::string error = ErrorOf([&] { ImageDataset(dir, {}); });
  EXPECT_NE(error.find("frame 1 is missing: no " + dir + "/image_0/000001.png (the next image is 000002.png)"),
            std::string::npos)
      << error;
  // Numbering that does not start at 0 is the same misalignment.
  const std::string dir2 = MakeVdoDataset("vdo_late_start");
  for (const char* sub : {"image_0", "depth", "mask"}) fs::remove(dir2 + "/" + sub + "/" + Name(0, "png"));
  EXPECT_NE(ErrorOf([&] { ImageDataset(dir2, {}); }).find("frame 0 is missing"), std::string::npos);
  // Names that are not frame numbers are read in order, as before.
  const std::string dir3 = MakeVdoDataset("vdo_named");
  for (const char* sub : {"image_0", "depth", "mask"})
    for (int k = 0; k < 3; ++k)
      fs::rename(dir3 + "/" + sub + "/" + Name(k, "png"), dir3 + "/" + sub + "/" + std::string("f") + Name(k, "png"));
  EXPECT_EQ(ImageDataset(dir3, {}).size(), 3);
}

TEST(ImageDataset, DisparityDepthNeedsAStereoCalibration) {
  const std::string dir = MakeVdoDataset("vdo_disparity");
  ImageDatasetOptions options;
  options.depth_encoding = "disparity_x256";
  EXPECT_NE(ErrorOf([&] { ImageDataset(dir, options); }).find("stereo calibration"), std::string::npos);
  WriteCalib(dir + "/calib.txt", 25.0);  // fx * baseline = 25: baseline 0.5 m
  const ImageDataset data(dir, options);
  // depth PNG value 1000 = disparity 1000 / 256 px -> z = 25 / 3.90625 = 6.4 m
  EXPECT_NEAR(data.read(0).depth_m.at<float>(1, 1), 6.4f, 1e-4);
}

TEST(ImageDataset, KittiRawTakesDepthFromTheLidarAndNamesATruncatedScan) {
  const std::string dir = test::TempDir("kitti_raw");
  fs::create_directories(dir + "/image_02");
  fs::create_directories(dir + "/velodyne_points");
  WriteCalib(dir + "/calib.txt");
  for (int k = 0; k < 2; ++k) {
    dslam::WritePngFile(dir + "/image_02/" + Name(k, "png"), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(90)));
    // One point 8 m ahead of the camera (LiDAR x forward): Tr_velo_to_cam maps (8, 0, 0) to z = 8.
    const float record[4] = {8.0f, 0.0f, 0.0f, 0.3f};
    std::ofstream scan(dir + "/velodyne_points/" + Name(k, "bin"), std::ios::binary);
    scan.write(reinterpret_cast<const char*>(record), k == 0 ? 16 : 10);  // the second scan is cut short
  }
  const ImageDataset data(dir, {});
  EXPECT_EQ(data.layout(), "kitti-raw");
  EXPECT_FALSE(data.hasMasks());
  const ImageFrame f = data.read(0);
  EXPECT_FLOAT_EQ(f.depth_m.at<float>(24, 32), 8.0f);
  EXPECT_FLOAT_EQ(f.depth_m.at<float>(26, 34), 8.0f);  // spread by lidar_fill_radius_px = 2
  EXPECT_EQ(cv::countNonZero(f.depth_m), 25);
  EXPECT_NE(ErrorOf([&] { data.read(1); }).find("not a whole number of 16-byte"), std::string::npos);

  // Without Tr_velo_to_cam every LiDAR point would land nowhere: zero depth and a run that says nothing.
  std::ofstream(dir + "/calib.txt") << "P2: 50 0 32 0 0 50 24 0 0 0 1 0\nR0_rect: 1 0 0 0 1 0 0 0 1\n";
  EXPECT_NE(ErrorOf([&] { ImageDataset(dir, {}); }).find(dir + "/calib.txt: missing Tr_velo_to_cam"), std::string::npos);
  // Absurd intrinsics are a corrupt file.
  std::ofstream(dir + "/calib.txt") << "P2: 1e300 0 32 0 0 50 24 0 0 0 1 0\nR0_rect: 1 0 0 0 1 0 0 0 1\n";
  EXPECT_NE(ErrorOf([&] { ImageDataset(dir, {}); }).find("beyond 1e5 pixels"), std::string::npos);
}

}  // namespace
}  // namespace dslam

namespace dslam {
namespace {

TEST(ImageDataset, KittiTrackingLayoutTakesDepthFromTheStereoPairAndMasksFromTheLabels) {
  const std::string dir = test::TempDir("kitti_tracking_layout");
  for (const char* sub : {"image_02/0007", "image_03/0007", "calib", "label_02"}) fs::create_directories(dir + "/" + sub);
  constexpr int kWide = 320, kHigh = 120;
  const double fx = 200.0, baseline = 0.5, disparity = 10.0;  // every pixel 10 m away
  {
    std::ofstream calib(dir + "/calib/0007.txt");
    for (int i = 0; i < 4; ++i)
      calib << 'P' << i << ": " << fx << " 0 160 " << (i == 3 ? -fx * baseline : 0.0) << " 0 " << fx
            << " 60 0 0 0 1 0\n";
    calib << "R0_rect: 1 0 0 0 1 0 0 0 1\nTr_velo_to_cam: 0 -1 0 0 0 0 -1 0 1 0 0 0\n";
  }
  // A car (track 4) 10 m ahead: "frame track type truncated occluded alpha x1 y1 x2 y2 h w l X Y Z ry".
  std::ofstream(dir + "/label_02/0007.txt") << "0 4 Car 0 0 0 100 40 220 90 1.5 1.6 3.9 0 1.0 10 0\n";
  cv::Mat right(kHigh, kWide, CV_8UC1);
  cv::randu(right, 0, 255);
  cv::GaussianBlur(right, right, {3, 3}, 0.8);
  cv::Mat left;
  cv::warpAffine(right, left, cv::Matx23d(1, 0, disparity, 0, 1, 0), right.size(), cv::INTER_LINEAR,
                 cv::BORDER_REFLECT);
  dslam::WritePngFile(dir + "/image_02/0007/000000.png", left);
  dslam::WritePngFile(dir + "/image_03/0007/000000.png", right);

  const ImageDataset data(dir, ImageDatasetOptions{});
  EXPECT_EQ(data.layout(), "kitti-tracking");
  EXPECT_EQ(data.name(), "0007");
  const ImageFrame f = data.read(0);
  std::vector<float> z;
  for (int v = 20; v < 100; ++v)
    for (int u = 150; u < 300; ++u)
      if (f.depth_m.at<float>(v, u) > 0.0f) z.push_back(f.depth_m.at<float>(v, u));
  ASSERT_GT(z.size(), 5000u);
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  EXPECT_NEAR(z[z.size() / 2], fx * baseline / disparity, 0.3);
  // The mask is the projected box: the box centre (X 0, Y 1 - h/2, Z 10) is at (160, 60 + 200 * 0.25 / 10).
  EXPECT_EQ(f.instance_ids.at<int32_t>(65, 160), 5);  // object id = track id + 1
  EXPECT_EQ(f.instance_ids.at<int32_t>(10, 10), 0);
}

}  // namespace
}  // namespace dslam
