#pragma once
// A vehicle's sensors on DDS: writers of colour (bgr8), depth (32FC1), instance mask (16UC1), odometry
// (the camera pose in the odometry frame) and, for a vehicle with a LiDAR, its scans (PointCloud2 in the
// LiDAR's frame) under the vehicle's topic namespace. With compression, the images go as
// sensor_msgs/CompressedImage on <image topic>/compressed instead (plugin/compressed_image.h). Used by
// `dslam publish` and the latency benchmark; no Fast DDS type appears in this header.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "data/image_frame.h"
#include "plugin/compressed_image.h"

namespace dslam {

// A frame's messages, encoded (images compressed as the publisher that made it compresses them) and ready
// to send: what a camera that encodes in hardware hands its driver. Opaque (no Fast DDS type here).
class EncodedSensorFrame {
 public:
  ~EncodedSensorFrame();
  EncodedSensorFrame(EncodedSensorFrame&&) noexcept;
  EncodedSensorFrame& operator=(EncodedSensorFrame&&) noexcept;
  size_t bytes() const;  // the payloads it holds

 private:
  friend class SensorPublisher;
  struct Messages;
  explicit EncodedSensorFrame(std::unique_ptr<Messages> messages);
  std::unique_ptr<Messages> messages_;
};

class SensorPublisher {
 public:
  // Throws std::runtime_error when the participant or a writer cannot be created.
  SensorPublisher(int domain_id, const std::string& profiles_file, const std::string& vehicle, bool with_lidar = false,
                  ImageCompression compression = ImageCompression::kNone);
  ~SensorPublisher();
  SensorPublisher(const SensorPublisher&) = delete;
  SensorPublisher& operator=(const SensorPublisher&) = delete;

  // Waits until every input topic has a reader (discovery takes a moment), at most `timeout_s`.
  bool waitForReaders(double timeout_s, const std::atomic<bool>* stop = nullptr);
  // The frame's images with its stamp; the odometry pose too when `with_odometry`, with the odometry's
  // velocity uncertainty (per second) in the twist covariance's diagonal, as a wheel-odometry driver
  // fills it (zero: none).
  // `scan_lidar`: the frame's LiDAR scan as recorded ("x y z intensity" in the LiDAR's frame), published
  // when the publisher was made with_lidar.
  void publish(const ImageFrame& frame, const SE3& T_odom_camera, const Vec6& twist_sigma_per_s, bool with_odometry,
               const std::vector<Eigen::Vector4f>* scan_lidar = nullptr);
  // The same in two steps: the messages encoded, then sent with every header stamped `t_ns`.
  EncodedSensorFrame encode(const ImageFrame& frame, const SE3& T_odom_camera, const Vec6& twist_sigma_per_s,
                            bool with_odometry, const std::vector<Eigen::Vector4f>* scan_lidar = nullptr) const;
  void publish(EncodedSensorFrame& frame, int64_t t_ns);
  // Lets reliable writers deliver what is queued: returns once every reliable reader has acknowledged
  // it, at most 10 s (a reader that discovers this writer late asks for it at the next heartbeat).
  void flush();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dslam
