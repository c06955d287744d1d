#pragma once
// sensor_msgs/CompressedImage <-> the front-end's images, as ROS 2's image_transport sends them on
// <image topic>/compressed: a link of 100 Mbit/s cannot carry raw KITTI-size colour, depth and mask at
// 10 Hz (~4 MB a frame), and on a lossy link every sample's ~700 fragments must all arrive
// (docs/serve.md, "The vehicle network"). Colour goes as PNG (lossless) or JPEG, depth as 16-bit PNG in
// millimetres (what depth cameras send; beyond 65.535 m a pixel has no depth), masks as 16-bit PNG.
// Every sample is checked before decoding (format, PNG chunks and checksums, JPEG markers, pixel count);
// errors are returned as a message naming the sample and the problem, nothing throws on bad samples.

#include <cstdint>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "plugin/image_message.h"
#include "sensor_msgs_CompressedImage.h"

namespace dslam {

enum class ImageCompression { kNone, kPng, kJpeg };

// "none", "png" or "jpeg"; std::nullopt for anything else.
std::optional<ImageCompression> ParseImageCompression(const std::string& name);

// The images' compressed form: colour as `compression` says (PNG or JPEG at quality 90), depth and mask as
// PNG whatever it says (JPEG would blur depth edges and mix instance ids). Throws std::invalid_argument for
// kNone or a mask with ids above 65535 (PNG holds 16 bits: send such masks uncompressed).
sensor_msgs::msg::CompressedImage EncodeCompressedImage(const cv::Mat& image, ImageRole role,
                                                        ImageCompression compression, int64_t t_ns,
                                                        const std::string& frame_id);

// The same types as DecodeImage: colour CV_8UC3 BGR or CV_8UC1, depth CV_32FC1 metres (0: none), mask CV_16UC1.
// Accepts the formats "png", "jpeg", "<enc>; png compressed <enc>", "<enc>; jpeg compressed <enc>" and, for
// depth, "16UC1; compressedDepth png" (its 12-byte header skipped); 32FC1 compressedDepth (inverse depth
// quantised) is refused by name.
DecodedImage DecodeCompressedImage(const sensor_msgs::msg::CompressedImage& msg, ImageRole role);

}  // namespace dslam
