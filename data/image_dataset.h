#pragma once
// Recorded image sequences on disk, read one frame at a time (nothing is held in memory but the file
// lists). Layouts, found from the folder's content:
//  - VDO-SLAM / DynoSAM ("vdo"): image_0/NNNNNN.png, depth/NNNNNN.png (16-bit depth in mm, or disparity
//    x256 with depth_encoding = disparity_x256), mask/NNNNNN.png (16-bit ids) or semantic/NNNNNN.txt,
//    optional flow/NNNNNN.flo (frame k -> k+1), calib.txt (KITTI P0..P3), optional odometry.txt,
//    times.txt and ground truth (pose_gt.txt, object_pose.txt, object_category.txt). `dslam render-scene`
//    writes this layout.
//  - KITTI tracking ("kitti-tracking"): image_02/SSSS/ and image_03/SSSS/ (depth by stereo matching),
//    calib/SSSS.txt; label_02/SSSS.txt, when present, gives box-shaped instance masks and, with oxts/ or
//    pose_gt, the ground truth.
//  - KITTI raw ("kitti-raw"): image_02/*.png with velodyne_points/*.bin (LiDAR depth) or image_03/*.png
//    (stereo depth), calib.txt. No masks, no ground truth.
// This reader links OpenCV (imgcodecs); it lives beside the other readers but in the vision library.

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "data/depth_maps.h"
#include "data/image_frame.h"
#include "data/kitti_dataset.h"
#include "geometry/pinhole_camera.h"

namespace dslam {

struct ImageDatasetOptions {
  std::string sequence;                   // KITTI tracking layout: which SSSS (optional when there is one)
  std::string depth_encoding = "depth_mm";  // of depth/ PNGs: depth_mm | disparity_x256; or stereo (image_1/, SGBM)
  int lidar_fill_radius_px = 2;           // sparse LiDAR depth spread to neighbours within this radius
  bool read_flow = true;                  // read flow/*.flo when the folder has it
  StereoParams stereo;
  // Images (PNG) with more pixels are refused from their header, before any is decoded.
  int64_t max_image_pixels = 50'000'000;
  // The frame rate speeds are measured at: the dataset's own times (times.txt: the median step) when it has
  // them, else frame_rate_hz. override_times: frame k is at k / frame_rate_hz whatever times.txt says (for
  // datasets whose times are known wrong, e.g. VDO-SLAM's KITTI layout, whose steps are 0.05 s at 10 Hz).
  double frame_rate_hz = 10.0;
  bool override_times = false;
  void validate() const;
};

class ImageDataset {
 public:
  // Throws std::runtime_error naming the folder or file that is missing or malformed.
  ImageDataset(const std::string& dir, const ImageDatasetOptions& options);

  const std::string& layout() const { return layout_; }
  const std::string& name() const { return name_; }
  int size() const { return static_cast<int>(images_.size()); }
  const PinholeCamera& camera() const { return camera_; }
  int64_t stampNs(int k) const { return t_ns_.at(static_cast<size_t>(k)); }  // frame k's time stamp
  double frameRateHz() const { return frame_rate_hz_; }
  // Where frameRateHz() comes from ("times.txt" or "dataset.frame_rate_hz"), and what was suspicious but
  // possible in the dataset's files (e.g. a step of times.txt far from the others), each naming file and line.
  const std::string& frameRateSource() const { return frame_rate_source_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  bool hasMasks() const { return mask_kind_ != MaskKind::kNone; }
  bool hasOdometry() const { return !odometry_.empty(); }
  bool hasFlow() const { return !flows_.empty(); }
  bool hasLidar() const { return depth_kind_ == DepthKind::kLidar; }

  // Frame k (0-based): throws std::runtime_error naming the file that is missing, unreadable or of the
  // wrong size or pixel type.
  ImageFrame read(int k) const;
  // The odometry increment into frame k (none for the first frame or without odometry.txt), without
  // reading the frame's images.
  std::optional<OdometryMeasurement> odometryAt(int k) const;
  // With LiDAR (hasLidar()): frame k's scan as recorded, in the LiDAR's frame ("x y z reflectance"),
  // before read() takes it into the camera's.
  std::vector<Eigen::Vector4f> readLidarScan(int k) const;

  // Ground truth when the folder has it (camera poses at least).
  const std::optional<KittiGroundTruthSequence>& groundTruth() const { return ground_truth_; }

  // For studies of imperfect inputs (dslam study): `transform` is applied to every frame read, after
  // decoding and checking; and the ground truth can be replaced to follow what it changed (e.g. the object
  // ids a degraded segmenter gives).
  void setFrameTransform(std::function<void(ImageFrame&)> transform) { transform_ = std::move(transform); }
  void setGroundTruth(KittiGroundTruthSequence gt) { ground_truth_ = std::move(gt); }

 private:
  enum class MaskKind { kNone, kPng16, kSemanticText, kLabelBoxes };
  enum class DepthKind { kPngDepthMm, kPngDisparity, kStereo, kLidar };

  cv::Mat readDepth(int k, const cv::Mat& left, ImageFrame* frame) const;
  cv::Mat readMask(int k) const;

  ImageDatasetOptions options_;
  std::string dir_, layout_, name_;
  PinholeCamera camera_;
  double baseline_m_ = 0.0;
  Eigen::Matrix<double, 3, 4> P_camera_lidar_ = Eigen::Matrix<double, 3, 4>::Zero();
  Eigen::Matrix<double, 3, 4> T_camera_lidar_ = Eigen::Matrix<double, 3, 4>::Zero();  // metric, [R | t]
  std::vector<std::string> images_, depths_, masks_, flows_, rights_;
  DepthKind depth_kind_ = DepthKind::kPngDepthMm;
  MaskKind mask_kind_ = MaskKind::kNone;
  std::vector<int64_t> t_ns_;
  double frame_rate_hz_ = 10.0;
  std::string frame_rate_source_ = "dataset.frame_rate_hz";
  std::vector<std::string> warnings_;
  std::map<int, OdometryMeasurement> odometry_;
  struct LabelShape {
    double distance_m = 0.0;
    int object_id = 0;
    std::vector<cv::Point> hull;  // of the projected 3D box
  };
  std::map<int, std::vector<LabelShape>> label_shapes_;  // frame -> labelled objects, farthest first
  std::optional<KittiGroundTruthSequence> ground_truth_;
  std::function<void(ImageFrame&)> transform_;
};

}  // namespace dslam
