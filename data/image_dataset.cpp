#include "data/image_dataset.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <future>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "data/dense_maps.h"
#include "data/image_codec.h"
#include "data/odometry_file.h"
#include "data/png_check.h"
#include "data/velodyne.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

std::vector<std::string> FilesWithExtension(const fs::path& dir, const std::string& ext) {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().extension() == ext) files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

// Frame k is the image whose name is number k: images numbered by their names (000000.png, ...) must be
// 0, 1, 2, ... with no gap, or every later image would pair with another frame's times, odometry and
// ground truth. Throws naming the first missing frame. Names that are not numbers are taken in order.
void RequireConsecutiveFrameNumbers(const std::vector<std::string>& images) {
  auto number_of = [](const std::string& path, long long* n) {
    const std::string stem = fs::path(path).stem().string();
    if (stem.empty() || stem.size() > 18 || !std::all_of(stem.begin(), stem.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return false;
    *n = std::stoll(stem);
    return true;
  };
  std::vector<long long> numbers;
  for (const std::string& image : images) {
    long long n = 0;
    if (!number_of(image, &n)) return;
    numbers.push_back(n);
  }
  for (size_t k = 0; k < numbers.size(); ++k) {
    if (numbers[k] == static_cast<long long>(k)) continue;
    const fs::path found(images[k]);
    char expected[64];
    std::snprintf(expected, sizeof expected, "%0*zu%s", static_cast<int>(found.stem().string().size()), k,
                  found.extension().string().c_str());
    throw std::runtime_error("frame " + std::to_string(k) + " is missing: no " + (found.parent_path() / expected).string() +
                             " (the next image is " + found.filename().string() +
                             "); frames are numbered by their file names from 0 without gaps, and times, odometry "
                             "and ground truth are matched to them by that number");
  }
}

// The file of `dir` with the same stem as each image, in image order; throws naming the first missing one.
std::vector<std::string> Matching(const std::vector<std::string>& images, const fs::path& dir, const std::string& ext,
                                  size_t how_many) {
  std::vector<std::string> out;
  for (size_t k = 0; k < how_many; ++k) {
    const fs::path p = dir / (fs::path(images[k]).stem().string() + ext);
    if (!fs::is_regular_file(p))
      throw std::runtime_error("missing " + p.string() + " (for image " + images[k] + ")");
    out.push_back(p.string());
  }
  return out;
}

std::string Size(const cv::Mat& m) { return std::to_string(m.cols) + "x" + std::to_string(m.rows); }

// A file's bytes, refused by name when missing, empty or a damaged, cut or oversized PNG (FindPngProblem).
std::vector<uint8_t> ReadCheckedBytes(const std::string& path, int64_t max_pixels) {
  std::vector<uint8_t> bytes = ReadFileBytes(path);
  if (bytes.empty()) throw std::runtime_error("cannot read image " + path + " (missing or empty)");
  if (const std::string problem = FindPngProblem(bytes, max_pixels); !problem.empty())
    throw std::runtime_error("cannot read image " + path + ": " + problem);
  return bytes;
}

cv::Mat DecodeImage(const std::string& path, const std::vector<uint8_t>& bytes, ImageDecode mode) {
  std::string error;
  cv::Mat image = DecodePng(bytes, mode, &error);
  if (image.empty()) throw std::runtime_error("cannot read image " + path + ": " + error);
  return image;
}

cv::Mat ReadImage(const std::string& path, ImageDecode mode, int64_t max_pixels) {
  // The file is read once: its structure checked from the bytes, then the same bytes decoded.
  return DecodeImage(path, ReadCheckedBytes(path, max_pixels), mode);
}

// An image's width and height; a PNG's from its header (the file checked whole, as ReadImage checks it)
// without decoding its pixels, which its frame's reading does anyway.
cv::Size ReadImageSize(const std::string& path, int64_t max_pixels) {
  const std::vector<uint8_t> bytes = ReadCheckedBytes(path, max_pixels);
  if (const std::optional<PngSize> size = ReadPngSize(bytes))
    return cv::Size(static_cast<int>(size->width), static_cast<int>(size->height));
  return DecodeImage(path, bytes, ImageDecode::kUnchanged).size();  // not a PNG: the decoder says why
}

}  // namespace

void ImageDatasetOptions::validate() const {
  if (depth_encoding != "depth_mm" && depth_encoding != "disparity_x256" && depth_encoding != "stereo")
    throw std::invalid_argument("unknown depth encoding '" + depth_encoding +
                                "' (expected depth_mm, disparity_x256 or stereo)");
  if (lidar_fill_radius_px < 0 || lidar_fill_radius_px > 50)
    throw std::invalid_argument("dataset lidar_fill_radius_px must be in 0..50");
  if (!(frame_rate_hz >= 0.1 && frame_rate_hz <= 1000.0))
    throw std::invalid_argument("dataset frame_rate_hz must be in 0.1..1000");
  if (max_image_pixels < 1 || max_image_pixels > 1'000'000'000)
    throw std::invalid_argument("dataset max_image_pixels must be in 1..1e9");
  stereo.validate();
}

ImageDataset::ImageDataset(const std::string& dir, const ImageDatasetOptions& options) : options_(options), dir_(dir) {
  options_.validate();
  const fs::path root(dir);
  if (!fs::is_directory(root)) throw std::runtime_error("dataset directory " + dir + " does not exist");
  name_ = root.filename().string();
  std::optional<KittiCalibration> calib;
  auto read_calib = [&](const fs::path& p) {
    if (!fs::is_regular_file(p)) throw std::runtime_error("missing calibration " + p.string());
    calib = ReadKittiCalibration(p.string());
  };

  if (fs::is_directory(root / "image_0")) {
    layout_ = "vdo";
    images_ = FilesWithExtension(root / "image_0", ".png");
    if (images_.empty()) throw std::runtime_error("no .png images in " + (root / "image_0").string());
    RequireConsecutiveFrameNumbers(images_);
    read_calib(root / "calib.txt");
    if (options_.depth_encoding == "stereo") {
      // Depth from the rectified pair by semi-global matching, as on real KITTI (render-scene --stereo).
      if (!fs::is_directory(root / "image_1"))
        throw std::runtime_error("missing right images " + (root / "image_1").string() +
                                 " (dataset.depth_encoding: stereo; render-scene --stereo writes them)");
      rights_ = Matching(images_, root / "image_1", ".png", images_.size());
      depth_kind_ = DepthKind::kStereo;
    } else {
      if (!fs::is_directory(root / "depth")) throw std::runtime_error("missing depth folder " + (root / "depth").string());
      depths_ = Matching(images_, root / "depth", ".png", images_.size());
      depth_kind_ = options_.depth_encoding == "depth_mm" ? DepthKind::kPngDepthMm : DepthKind::kPngDisparity;
    }
    if (fs::is_directory(root / "mask")) {
      masks_ = Matching(images_, root / "mask", ".png", images_.size());
      mask_kind_ = MaskKind::kPng16;
    } else if (fs::is_directory(root / "semantic")) {
      masks_ = Matching(images_, root / "semantic", ".txt", images_.size());
      mask_kind_ = MaskKind::kSemanticText;
    }
    if (options_.read_flow && fs::is_directory(root / "flow"))
      flows_ = Matching(images_, root / "flow", ".flo", images_.size() - 1);  // none after the last frame
    if (fs::is_regular_file(root / "odometry.txt")) odometry_ = ReadOdometryFile((root / "odometry.txt").string());
    if (fs::is_regular_file(root / "pose_gt.txt")) ground_truth_ = LoadKittiGroundTruth(dir, "");
  } else if (fs::is_directory(root / "image_02")) {
    std::string seq = options_.sequence;
    if (seq.empty())
      for (const auto& entry : fs::directory_iterator(root / "image_02"))
        if (entry.is_directory()) {
          if (!seq.empty()) throw std::runtime_error(dir + " holds several sequences: choose one with --seq");
          seq = entry.path().filename().string();
        }
    if (!seq.empty()) {
      layout_ = "kitti-tracking";
      name_ = seq;
      const fs::path left = root / "image_02" / seq, right = root / "image_03" / seq;
      if (!fs::is_directory(left)) throw std::runtime_error("missing image folder " + left.string());
      if (!fs::is_directory(right))
        throw std::runtime_error("missing right images " + right.string() + " (depth comes from the stereo pair)");
      images_ = FilesWithExtension(left, ".png");
      if (images_.empty()) throw std::runtime_error("no .png images in " + left.string());
      RequireConsecutiveFrameNumbers(images_);
      rights_ = Matching(images_, right, ".png", images_.size());
      depth_kind_ = DepthKind::kStereo;
      read_calib(root / "calib" / (seq + ".txt"));
      const fs::path labels = root / "label_02" / (seq + ".txt");
      if (fs::is_regular_file(labels)) {
        mask_kind_ = MaskKind::kLabelBoxes;
        const auto& P = calib->P[2];
        for (const KittiLabel& l : ReadKittiLabels(labels.string())) {
          const SE3 T_camera_object = ObjectPoseFromLabel(l.bottom_centre_camera, l.rotation_y);
          std::vector<cv::Point2f> corners;
          bool behind = false;
          for (int i = 0; i < 8; ++i) {
            const Vec3 c_object((i & 1 ? 0.5 : -0.5) * l.l, (i & 2 ? -l.h : 0.0), (i & 4 ? 0.5 : -0.5) * l.w);
            const Vec3 c = T_camera_object * c_object;
            if (c.z() < 0.1) behind = true;
            const Eigen::Vector3d x = P * c.homogeneous();
            corners.emplace_back(static_cast<float>(x.x() / x.z()), static_cast<float>(x.y() / x.z()));
          }
          if (behind) continue;
          LabelShape shape;
          shape.distance_m = l.bottom_centre_camera.norm();
          shape.object_id = l.track_id + 1;  // as VDO-SLAM's object ids
          std::vector<cv::Point2f> hull;
          cv::convexHull(corners, hull);
          for (const auto& p : hull) shape.hull.emplace_back(cvRound(p.x), cvRound(p.y));
          label_shapes_[l.frame].push_back(std::move(shape));
        }
        for (auto& [frame, shapes] : label_shapes_)
          std::sort(shapes.begin(), shapes.end(),
                    [](const LabelShape& a, const LabelShape& b) { return a.distance_m > b.distance_m; });
      }
      if (fs::is_regular_file(root / "oxts" / (seq + ".txt")) || fs::is_directory(root / "gt" / seq))
        ground_truth_ = LoadKittiGroundTruth(dir, seq);
    } else {
      layout_ = "kitti-raw";
      images_ = FilesWithExtension(root / "image_02", ".png");
      if (images_.empty()) throw std::runtime_error("no .png images in " + (root / "image_02").string());
      RequireConsecutiveFrameNumbers(images_);
      read_calib(root / "calib.txt");
      if (fs::is_directory(root / "velodyne_points")) {
        if (!calib->has_T_cam_velo)
          throw std::runtime_error((root / "calib.txt").string() +
                                   ": missing Tr_velo_to_cam (LiDAR depth needs the Velodyne-to-camera transform)");
        depths_ = Matching(images_, root / "velodyne_points", ".bin", images_.size());
        depth_kind_ = DepthKind::kLidar;
        P_camera_lidar_ = calib->P_camera_lidar();
        T_camera_lidar_ = calib->T_camera_lidar();
      } else if (fs::is_directory(root / "image_03")) {
        rights_ = Matching(images_, root / "image_03", ".png", images_.size());
        depth_kind_ = DepthKind::kStereo;
      } else {
        throw std::runtime_error(dir + ": no depth source (expected velodyne_points/ or image_03/)");
      }
    }
  } else {
    throw std::runtime_error(dir + " is not an image dataset: expected image_0/ (VDO-SLAM layout) or image_02/ (KITTI)");
  }

  // Camera: the left colour camera (P2) when it is given, else P0; the size from the first image.
  const auto& P = calib->P[2](0, 0) > 0.0 ? calib->P[2] : calib->P[0];
  camera_.fx = P(0, 0), camera_.fy = P(1, 1), camera_.cx = P(0, 2), camera_.cy = P(1, 2);
  const cv::Size first = ReadImageSize(images_.front(), options_.max_image_pixels);
  camera_.width = first.width, camera_.height = first.height;
  // Focal lengths in normalised units (0.58 for 721 px) parse, and then every depth and motion is wrong: a
  // pinhole camera's field of view across its image is between about 1 and 170 degrees.
  for (const double f : {camera_.fx, camera_.fy})
    if (!(f >= 0.05 * camera_.width && f <= 50.0 * camera_.width))
      throw std::runtime_error(dir + ": calibration focal length " + std::to_string(f) + " px is implausible for " +
                               std::to_string(camera_.width) + " px wide images (expected " +
                               std::to_string(0.05 * camera_.width) + " to " + std::to_string(50.0 * camera_.width) +
                               " px; a calibration in normalised units?)");
  baseline_m_ = (calib->P[2](0, 3) - calib->P[3](0, 3)) / camera_.fx;
  if ((depth_kind_ == DepthKind::kStereo || depth_kind_ == DepthKind::kPngDisparity) && !(baseline_m_ > 0.0))
    throw std::runtime_error(dir + ": depth from disparity needs a stereo calibration (P2 and P3 with a baseline)");

  frame_rate_hz_ = options_.frame_rate_hz;
  if (fs::is_regular_file(root / "times.txt") && !options_.override_times) {
    const std::string path = (root / "times.txt").string();
    const auto times = ReadTimes(path);
    if (times.size() < images_.size())
      throw std::runtime_error(path + ": " + std::to_string(times.size()) + " timestamps for " +
                               std::to_string(images_.size()) + " images");
    for (size_t k = 0; k < images_.size(); ++k) t_ns_.push_back(static_cast<int64_t>(std::llround(times[k] * 1e9)));
    if (images_.size() >= 2) {
      // The rate speeds are measured at is the dataset's own: its median step. A step far from it (a dropped
      // frame, a stall) is possible, and said.
      std::vector<double> steps;
      for (size_t k = 1; k < images_.size(); ++k) steps.push_back(times[k] - times[k - 1]);
      std::vector<double> sorted = steps;
      // The lower median: with an even count it leans to the nominal step, not to a stall's.
      const size_t mid = (sorted.size() - 1) / 2;
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(mid), sorted.end());
      const double median_step = sorted[mid];
      frame_rate_hz_ = 1.0 / median_step;
      frame_rate_source_ = "times.txt";
      if (!(frame_rate_hz_ >= 0.1 && frame_rate_hz_ <= 1000.0))
        throw std::runtime_error(path + ": its median step of " + std::to_string(median_step) +
                                 " s is no camera's frame rate (0.1 to 1000 Hz); times in other units?");
      int uneven = 0;
      for (size_t k = 0; k < steps.size(); ++k) {
        if (std::abs(steps[k] - median_step) <= 0.25 * median_step) continue;
        if (uneven++ == 0)
          warnings_.push_back(path + ":" + std::to_string(k + 2) + ": a step of " + std::to_string(steps[k]) +
                              " s where the others are about " + std::to_string(median_step) + " s");
      }
      if (uneven > 1) warnings_.back() += " (and " + std::to_string(uneven - 1) + " more such steps)";
    }
  } else {
    for (size_t k = 0; k < images_.size(); ++k)
      t_ns_.push_back(static_cast<int64_t>(std::llround(k * 1e9 / options_.frame_rate_hz)));
    if (fs::is_regular_file(root / "times.txt")) frame_rate_source_ = "dataset.frame_rate_hz (override_times)";
  }
  if (ground_truth_ && static_cast<int>(ground_truth_->T_world_camera.size()) < size())
    throw std::runtime_error(dir + ": ground truth has " + std::to_string(ground_truth_->T_world_camera.size()) +
                             " camera poses for " + std::to_string(size()) + " images");
}

cv::Mat ImageDataset::readDepth(int k, const cv::Mat& left, ImageFrame* frame) const {
  switch (depth_kind_) {
    case DepthKind::kPngDepthMm:
    case DepthKind::kPngDisparity: {
      const cv::Mat raw = ReadImage(depths_[k], ImageDecode::kUnchanged, options_.max_image_pixels);
      if (raw.channels() != 1 || raw.depth() != CV_16U)
        throw std::runtime_error(depths_[k] + ": depth PNG must be 16-bit single channel");
      return depth_kind_ == DepthKind::kPngDepthMm ? DepthFromScaledImage(raw, 1000.0)
                                                   : DepthFromDisparity(raw, 256.0, camera_.fx * baseline_m_);
    }
    case DepthKind::kStereo: {
      const cv::Mat right = ReadImage(rights_[k], ImageDecode::kColour, options_.max_image_pixels);
      if (right.size() != left.size())
        throw std::runtime_error(rights_[k] + " is " + Size(right) + " but the left image is " + Size(left));
      return DepthFromStereo(left, right, camera_.fx, baseline_m_, options_.stereo);
    }
    case DepthKind::kLidar: {
      const std::vector<Eigen::Vector4f> scan = ReadVelodyneScan(depths_[k]);
      SetLidarScan(scan, T_camera_lidar_, frame);
      return FillSparseDepth(DepthFromLidar(scan, P_camera_lidar_, camera_.width, camera_.height),
                             options_.lidar_fill_radius_px);
    }
  }
  return {};
}

cv::Mat ImageDataset::readMask(int k) const {
  switch (mask_kind_) {
    case MaskKind::kNone: return {};
    case MaskKind::kPng16: {
      cv::Mat mask = ReadImage(masks_[k], ImageDecode::kUnchanged, options_.max_image_pixels);
      if (mask.channels() != 1 || (mask.depth() != CV_16U && mask.depth() != CV_8U))
        throw std::runtime_error(masks_[k] + ": instance mask PNG must be 8- or 16-bit single channel");
      if (mask.depth() == CV_8U) mask.convertTo(mask, CV_16U);
      return mask;
    }
    case MaskKind::kSemanticText: {
      const InstanceMask m = ReadSemanticTxt(masks_[k]);
      cv::Mat mask(m.height, m.width, CV_32S);
      std::copy(m.ids.begin(), m.ids.end(), mask.ptr<int32_t>(0));
      return mask;
    }
    case MaskKind::kLabelBoxes: {
      cv::Mat mask(camera_.height, camera_.width, CV_32S, cv::Scalar(0));
      const auto shapes = label_shapes_.find(k);
      if (shapes != label_shapes_.end())
        for (const LabelShape& s : shapes->second) cv::fillConvexPoly(mask, s.hull, cv::Scalar(s.object_id));
      return mask;
    }
  }
  return {};
}

ImageFrame ImageDataset::read(int k) const {
  if (k < 0 || k >= size()) throw std::out_of_range("frame " + std::to_string(k) + " is outside the dataset");
  ImageFrame frame;
  frame.frame_index = k;
  frame.t_ns = t_ns_[k];
  // The depth (unless it comes from the stereo pair, which needs the colour image) and the mask are decoded
  // on a second thread while this one decodes the colour image: on two cores a frame is read in about the
  // time of its largest file (rendered 1242x375: 13 instead of 23 ms).
  const bool depth_alongside = depth_kind_ != DepthKind::kStereo;
  ImageFrame scan;  // the LiDAR scan, when the depth comes from one (set on the second thread)
  auto depth_and_mask = std::async(std::launch::async, [&] {
    std::pair<cv::Mat, cv::Mat> out;
    if (depth_alongside) out.first = readDepth(k, cv::Mat(), &scan);
    out.second = readMask(k);
    return out;
  });
  frame.image = ReadImage(images_[k], ImageDecode::kColour, options_.max_image_pixels);
  if (frame.image.cols != camera_.width || frame.image.rows != camera_.height)
    throw std::runtime_error(images_[k] + " is " + Size(frame.image) + " but the sequence's images are " +
                             std::to_string(camera_.width) + "x" + std::to_string(camera_.height));
  std::tie(frame.depth_m, frame.instance_ids) = depth_and_mask.get();
  if (!depth_alongside) frame.depth_m = readDepth(k, frame.image, &frame);
  frame.lidar_points_camera = std::move(scan.lidar_points_camera);
  frame.lidar_origin_camera = scan.lidar_origin_camera;
  frame.lidar_up_camera = scan.lidar_up_camera;
  if (frame.depth_m.size() != frame.image.size())
    throw std::runtime_error((depths_.empty() ? rights_[k] : depths_[k]) + ": depth is " + Size(frame.depth_m) +
                             " but the image is " + Size(frame.image));
  if (!frame.instance_ids.empty() && frame.instance_ids.size() != frame.image.size())
    throw std::runtime_error(masks_[k] + ": mask is " + Size(frame.instance_ids) + " but the image is " +
                             Size(frame.image));
  if (k < static_cast<int>(flows_.size())) {
    frame.flow_to_next = cv::Mat(frame.image.rows, frame.image.cols, CV_32FC2);
    ReadFloInto(flows_[k], frame.image.cols, frame.image.rows, frame.flow_to_next.ptr<float>(0));
  }
  frame.odometry = odometryAt(k);
  if (transform_) transform_(frame);
  return frame;
}

std::vector<Eigen::Vector4f> ImageDataset::readLidarScan(int k) const {
  if (k < 0 || k >= size()) throw std::out_of_range("frame " + std::to_string(k) + " is outside the dataset");
  if (depth_kind_ != DepthKind::kLidar) throw std::logic_error(dir_ + " has no LiDAR scans");
  return ReadVelodyneScan(depths_[k]);
}

std::optional<OdometryMeasurement> ImageDataset::odometryAt(int k) const {
  const auto o = odometry_.find(k);
  if (o == odometry_.end() || k == 0) return std::nullopt;
  return o->second;
}

}  // namespace dslam
