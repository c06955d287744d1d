#pragma once
// `dslam publish`: replays a recorded or rendered image sequence onto a vehicle's input topics as its
// sensors would: colour (bgr8), depth (32FC1 metres), instance mask (16UC1), odometry (the pose
// accumulated from the dataset's increments) and, from a dataset with LiDAR scans, the scans
// (PointCloud2 in the LiDAR's frame, rt/<vehicle>/lidar/points), with the dataset's stamps, at a fixed rate.

#include <atomic>
#include <ostream>
#include <string>

#include "data/image_dataset.h"
#include "plugin/compressed_image.h"

namespace dslam {

struct PublishOptions {
  int domain_id = 0;
  std::string profiles_file = "config/dds_profiles.xml";
  std::string vehicle;       // topic namespace ("" = rt/camera/...)
  double rate_hz = 10.0;
  int start_frame = 0;       // resume a replay (stamps continue where they were)
  int frames = 0;            // 0: to the end
  double wait_for_reader_s = 10.0;  // wait this long for readers of every input topic before publishing
  // Stamp each frame with this host's clock as it is published, as a camera driver stamps its captures,
  // instead of the dataset's own times: subscribers can then measure the latency from capture.
  bool stamp_now = false;
  // Images as sensor_msgs/CompressedImage on <topic>/compressed (colour PNG or JPEG, depth and mask PNG):
  // what fits a vehicle's 100 Mbit/s link (docs/serve.md, "The vehicle network").
  ImageCompression compression = ImageCompression::kNone;
  // Read and encode every frame before the first is sent, and send them as they are at the rate: a camera
  // host with an encoder of its own (hardware JPEG) costs the host it shares a processor with nothing per
  // frame. Holds every encoded frame in memory.
  bool preload = false;
};

// Returns the number of frames published; stops early when *stop becomes true. Throws
// std::runtime_error when the participant cannot be created or a frame cannot be read.
int PublishDataset(const ImageDataset& dataset, const PublishOptions& options, std::ostream& log,
                   const std::atomic<bool>* stop = nullptr);

}  // namespace dslam
