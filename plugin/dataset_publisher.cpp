#include "plugin/dataset_publisher.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <utility>
#include <vector>

#include "plugin/sensor_publisher.h"

namespace dslam {

int PublishDataset(const ImageDataset& dataset, const PublishOptions& options, std::ostream& log,
                   const std::atomic<bool>* stop) {
  // Finite and within what a sensor does: a period longer than a day is a typo, not a sensor.
  if (!std::isfinite(options.rate_hz) || options.rate_hz < 1e-3 || options.rate_hz > 1000.0)
    throw std::invalid_argument("--rate must be between 0.001 and 1000 Hz, got " + std::to_string(options.rate_hz));
  if (!std::isfinite(options.wait_for_reader_s) || options.wait_for_reader_s < 0.0 || options.wait_for_reader_s > 3600.0)
    throw std::invalid_argument("--wait must be between 0 and 3600 s, got " + std::to_string(options.wait_for_reader_s));
  if (options.frames < 0) throw std::invalid_argument("--frames must be 0 (to the end) or more, got " + std::to_string(options.frames));
  if (options.start_frame < 0 || options.start_frame >= dataset.size())
    throw std::invalid_argument("--start-frame " + std::to_string(options.start_frame) + " is outside the " +
                                std::to_string(dataset.size()) + " frames");
  SensorPublisher sensors(options.domain_id, options.profiles_file, options.vehicle, dataset.hasLidar(), options.compression);
  if (!sensors.waitForReaders(options.wait_for_reader_s, stop) && !(stop && *stop))
    log << "warning: no reader matched every input topic of vehicle '" << options.vehicle << "' within "
        << options.wait_for_reader_s << " s (--wait); publishing anyway, samples nobody reads are lost" << std::endl;

  // The vehicle's pose in its odometry frame, accumulated from the increments.
  SE3 T_odom_camera;
  for (int k = 1; k < options.start_frame; ++k)
    if (const auto odometry = dataset.odometryAt(k)) T_odom_camera = T_odom_camera * odometry->T_prev_curr;
  const int end = options.frames > 0 ? std::min(dataset.size(), options.start_frame + options.frames) : dataset.size();
  // Frame k read and encoded, with its own stamp.
  const auto prepare = [&](int k) {
    const ImageFrame frame = dataset.read(k);
    // The increment's sigmas, per second of the time it spans: a velocity's uncertainty, which the
    // receiver multiplies by the time between the frames it pairs.
    Vec6 twist_sigma_per_s = Vec6::Zero();
    if (frame.odometry) {
      T_odom_camera = T_odom_camera * frame.odometry->T_prev_curr;
      const double dt_s = static_cast<double>(frame.t_ns - dataset.stampNs(k - 1)) * 1e-9;
      if (dt_s > 0.0) twist_sigma_per_s = frame.odometry->sigma / dt_s;
    }
    std::vector<Eigen::Vector4f> scan;
    if (dataset.hasLidar()) scan = dataset.readLidarScan(k);  // as the LiDAR recorded it, in its own frame
    return std::make_pair(sensors.encode(frame, T_odom_camera, twist_sigma_per_s, dataset.hasOdometry(),
                                         dataset.hasLidar() ? &scan : nullptr),
                          frame.t_ns);
  };
  std::vector<std::pair<EncodedSensorFrame, int64_t>> preloaded;
  if (options.preload) {
    size_t bytes = 0;
    for (int k = options.start_frame; k < end && !(stop && *stop); ++k) {
      preloaded.push_back(prepare(k));
      bytes += preloaded.back().first.bytes();
      if ((k + 1) % 10 == 0 || k + 1 == end) log << "  encoded frame " << k + 1 << "/" << end << std::endl;
    }
    log << "  " << preloaded.size() << " frames encoded before sending, " << (bytes >> 20) << " MiB" << std::endl;
  }
  const auto period = std::chrono::duration<double>(1.0 / options.rate_hz);
  auto next = std::chrono::steady_clock::now();
  int published = 0;
  for (int k = options.start_frame; k < end && !(stop && *stop); ++k) {
    auto [encoded, t_ns] = options.preload ? std::move(preloaded[static_cast<size_t>(k - options.start_frame)]) : prepare(k);
    if (options.stamp_now)
      t_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
    sensors.publish(encoded, t_ns);
    ++published;
    if ((k + 1) % 10 == 0 || k + 1 == end) log << "  published frame " << k + 1 << "/" << end << std::endl;
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    // In short steps, so that a stop request (SIGINT, SIGTERM) is answered within 50 ms at any rate.
    while (std::chrono::steady_clock::now() < next && !(stop && *stop))
      std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(next - std::chrono::steady_clock::now(),
                                                                                 std::chrono::milliseconds(50)));
  }
  // Let reliable writers deliver what is queued before the participant goes (not when asked to stop).
  if (!(stop && *stop)) sensors.flush();
  return published;
}

}  // namespace dslam
