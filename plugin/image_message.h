#pragma once
// sensor_msgs/Image and nav_msgs/Odometry <-> the front-end's values, with every check a sample from
// the network needs: known encoding, data length = step x height, step >= width x pixel size, a depth
// or mask of the colour image's size, finite odometry. Errors are returned as a message naming the
// topic and the problem; nothing throws on bad samples.

#include <cstdint>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "nav_msgs_Odometry.h"
#include "plugin/frame_assembler.h"
#include "sensor_msgs_Image.h"

namespace dslam {

int64_t StampToNs(const builtin_interfaces::msg::Time& stamp);
builtin_interfaces::msg::Time NsToStamp(int64_t t_ns);

// What an image topic carries.
enum class ImageRole { kColour, kDepth, kMask };
// "colour image", "depth image", "instance mask": how errors name a sample.
const char* ImageRoleName(ImageRole role);

struct DecodedImage {
  cv::Mat image;      // colour: CV_8UC3 BGR or CV_8UC1; depth: CV_32FC1 metres; mask: CV_16UC1 or CV_32SC1 ids
  std::string error;  // empty when decoded
};

// Colour: bgr8, rgb8 (converted to BGR), mono8. Depth: 32FC1 (metres) or 16UC1 / mono16 (millimetres).
// Mask: 16UC1 / mono16 (instance ids, 0 = background).
DecodedImage DecodeImage(const sensor_msgs::msg::Image& msg, ImageRole role);
// Instance ids as a mask message carries them: 16-bit when every id fits (what a segmenter's driver sends),
// else 32-bit, so that no id is saturated into another; negative ids (background) become 0.
cv::Mat MaskForTransport(const cv::Mat& instance_ids);

// The inverse: bgr8 / mono8 colour, 32FC1 depth (metres), 16UC1 mask (32SC1 for a CV_32S mask: ids
// above 65535 kept).
sensor_msgs::msg::Image EncodeImage(const cv::Mat& image, ImageRole role, int64_t t_ns, const std::string& frame_id);

// nav_msgs/Odometry -> a stamped camera pose. The increment noise comes from the twist covariance's
// diagonal (per second, ROS order x y z roll pitch yaw; the assembler multiplies it by the time between
// frames) when all six are given, else from the configured default; the pose covariance, which is the
// drift accumulated over the drive, is not used.
std::optional<StampedPose> DecodeOdometry(const nav_msgs::msg::Odometry& msg, std::string* error);
// The inverse; `twist_sigma_per_s` goes into the twist covariance's diagonal (zero: none given).
nav_msgs::msg::Odometry EncodeOdometry(const SE3& T_world_camera, int64_t t_ns, const std::string& frame_id,
                                       const std::string& child_frame_id, const Vec6& twist_sigma_per_s = Vec6::Zero());

}  // namespace dslam
