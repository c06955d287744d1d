#include "plugin/image_message.h"

#include <cmath>
#include <cstring>

#include <opencv2/imgproc.hpp>

namespace dslam {

int64_t StampToNs(const builtin_interfaces::msg::Time& stamp) {
  return static_cast<int64_t>(stamp.sec()) * 1'000'000'000LL + static_cast<int64_t>(stamp.nanosec());
}

builtin_interfaces::msg::Time NsToStamp(int64_t t_ns) {
  builtin_interfaces::msg::Time stamp;
  int64_t sec = t_ns / 1'000'000'000LL, nsec = t_ns % 1'000'000'000LL;
  if (nsec < 0) nsec += 1'000'000'000LL, --sec;
  stamp.sec(static_cast<int32_t>(sec));
  stamp.nanosec(static_cast<uint32_t>(nsec));
  return stamp;
}

namespace {

// OpenCV type of an encoding allowed for the role; -1 when it is not.
int TypeOf(const std::string& encoding, ImageRole role) {
  switch (role) {
    case ImageRole::kColour:
      if (encoding == "bgr8" || encoding == "rgb8") return CV_8UC3;
      if (encoding == "mono8") return CV_8UC1;
      return -1;
    case ImageRole::kDepth:
      if (encoding == "32FC1") return CV_32FC1;
      if (encoding == "16UC1" || encoding == "mono16") return CV_16UC1;
      return -1;
    case ImageRole::kMask:
      if (encoding == "16UC1" || encoding == "mono16") return CV_16UC1;
      if (encoding == "32SC1") return CV_32SC1;  // ids above 65535
      return -1;
  }
  return -1;
}

}  // namespace

const char* ImageRoleName(ImageRole role) {
  switch (role) {
    case ImageRole::kColour: return "colour image";
    case ImageRole::kDepth: return "depth image";
    case ImageRole::kMask: return "instance mask";
  }
  return "image";
}

DecodedImage DecodeImage(const sensor_msgs::msg::Image& msg, ImageRole role) {
  DecodedImage out;
  const std::string what = std::string(ImageRoleName(role)) + " at " + std::to_string(StampToNs(msg.header().stamp())) + " ns";
  const int type = TypeOf(msg.encoding(), role);
  if (type < 0) {
    out.error = what + ": encoding '" + msg.encoding() + "' is not supported for this input";
    return out;
  }
  if (msg.width() == 0 || msg.height() == 0 || msg.width() > 16384 || msg.height() > 16384) {
    out.error = what + ": size " + std::to_string(msg.width()) + "x" + std::to_string(msg.height()) + " is not usable";
    return out;
  }
  const size_t pixel_bytes = CV_ELEM_SIZE(type);
  if (msg.step() < msg.width() * pixel_bytes) {
    out.error = what + ": step " + std::to_string(msg.step()) + " is smaller than width x " +
                std::to_string(pixel_bytes) + " bytes";
    return out;
  }
  if (msg.data().size() != static_cast<size_t>(msg.step()) * msg.height()) {
    out.error = what + ": " + std::to_string(msg.data().size()) + " bytes of data for step " +
                std::to_string(msg.step()) + " x height " + std::to_string(msg.height());
    return out;
  }
  const bool host_big_endian = false;  // x86-64 and ARM64 Linux
  if (pixel_bytes / CV_MAT_CN(type) > 1 && (msg.is_bigendian() != 0) != host_big_endian) {
    out.error = what + ": big-endian data is not supported";
    return out;
  }
  // Copy out of the sample (its buffer is returned to DDS).
  const cv::Mat view(static_cast<int>(msg.height()), static_cast<int>(msg.width()), type,
                     const_cast<uint8_t*>(msg.data().data()), msg.step());
  if (role == ImageRole::kColour && msg.encoding() == "rgb8")
    cv::cvtColor(view, out.image, cv::COLOR_RGB2BGR);
  else if (role == ImageRole::kDepth && type == CV_16UC1)
    view.convertTo(out.image, CV_32FC1, 1.0 / 1000.0);
  else
    out.image = view.clone();
  if (role == ImageRole::kDepth) cv::patchNaNs(out.image, 0.0);
  return out;
}

cv::Mat MaskForTransport(const cv::Mat& instance_ids) {
  double max_id = 0.0;
  cv::minMaxLoc(instance_ids, nullptr, &max_id);
  cv::Mat ids;
  if (max_id > 65535.0) {
    instance_ids.convertTo(ids, CV_32S);
    ids = cv::max(ids, 0);
  } else {
    instance_ids.convertTo(ids, CV_16U);  // saturates negatives to 0
  }
  return ids;
}

sensor_msgs::msg::Image EncodeImage(const cv::Mat& image, ImageRole role, int64_t t_ns, const std::string& frame_id) {
  sensor_msgs::msg::Image msg;
  msg.header().stamp(NsToStamp(t_ns));
  msg.header().frame_id(frame_id);
  msg.height(static_cast<uint32_t>(image.rows));
  msg.width(static_cast<uint32_t>(image.cols));
  switch (role) {
    case ImageRole::kColour: msg.encoding(image.channels() == 3 ? "bgr8" : "mono8"); break;
    case ImageRole::kDepth: msg.encoding("32FC1"); break;
    case ImageRole::kMask: msg.encoding(image.depth() == CV_32S ? "32SC1" : "16UC1"); break;
  }
  msg.is_bigendian(0);
  msg.step(static_cast<uint32_t>(image.cols * image.elemSize()));
  msg.data().resize(static_cast<size_t>(msg.step()) * image.rows);
  for (int v = 0; v < image.rows; ++v)
    std::memcpy(msg.data().data() + static_cast<size_t>(v) * msg.step(), image.ptr(v), msg.step());
  return msg;
}

std::optional<StampedPose> DecodeOdometry(const nav_msgs::msg::Odometry& msg, std::string* error) {
  const auto& p = msg.pose().pose().position();
  const auto& q = msg.pose().pose().orientation();
  const Eigen::Quaterniond quaternion(q.w(), q.x(), q.y(), q.z());
  const Vec3 t(p.x(), p.y(), p.z());
  const std::string what = "odometry at " + std::to_string(StampToNs(msg.header().stamp())) + " ns";
  if (!t.allFinite() || !quaternion.coeffs().allFinite()) {
    *error = what + ": pose is not finite";
    return std::nullopt;
  }
  if (std::abs(quaternion.norm() - 1.0) > 1e-3) {
    *error = what + ": orientation is not a unit quaternion";
    return std::nullopt;
  }
  StampedPose pose;
  pose.T_odom_camera = SE3(quaternion, t);
  // The increment's noise comes from the velocity's: the pose covariance is the drift accumulated since
  // the start of the drive, not the uncertainty of one step.
  Vec6 twist_sigma;
  int given = 0;
  for (int i = 0; i < 6; ++i) {
    const double variance = msg.twist().covariance()[static_cast<size_t>(7 * i)];
    if (!std::isfinite(variance) || variance < 0.0) {
      *error = what + ": twist covariance is not finite and non-negative";
      return std::nullopt;
    }
    twist_sigma[i] = std::sqrt(variance);
    given += variance > 0.0;
  }
  if (given == 6) pose.twist_sigma_per_s = twist_sigma;  // else the configured increment sigma
  return pose;
}

nav_msgs::msg::Odometry EncodeOdometry(const SE3& T_world_camera, int64_t t_ns, const std::string& frame_id,
                                       const std::string& child_frame_id, const Vec6& twist_sigma_per_s) {
  nav_msgs::msg::Odometry msg;
  msg.header().stamp(NsToStamp(t_ns));
  msg.header().frame_id(frame_id);
  msg.child_frame_id(child_frame_id);
  const Vec3& t = T_world_camera.translation();
  const Eigen::Quaterniond& q = T_world_camera.rotation();
  msg.pose().pose().position().x(t.x());
  msg.pose().pose().position().y(t.y());
  msg.pose().pose().position().z(t.z());
  msg.pose().pose().orientation().x(q.x());
  msg.pose().pose().orientation().y(q.y());
  msg.pose().pose().orientation().z(q.z());
  msg.pose().pose().orientation().w(q.w());
  for (int i = 0; i < 6; ++i)
    msg.twist().covariance()[static_cast<size_t>(7 * i)] = twist_sigma_per_s[i] * twist_sigma_per_s[i];
  return msg;
}

}  // namespace dslam
