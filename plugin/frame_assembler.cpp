#include "plugin/frame_assembler.h"

#include <stdexcept>

namespace dslam {

void AssemblerParams::validate() const {
  if (timeout_ns <= 0) throw std::invalid_argument("assembler timeout must be positive");
  if (silence_timeout_ns <= 0) throw std::invalid_argument("assembler silence timeout must be positive");
  if (max_pending < 1 || max_pending > 64) throw std::invalid_argument("max pending frame sets must be in 1..64");
  if (max_pending_bytes < (size_t{1} << 20)) throw std::invalid_argument("max pending bytes must be at least 1 MiB");
  if (nominal_period_ns < 0) throw std::invalid_argument("assembler nominal frame period must not be negative");
  if (!default_increment_sigma.allFinite() || (default_increment_sigma.array() <= 0.0).any())
    throw std::invalid_argument("assembler default odometry increment sigmas must be positive");
}

FrameAssembler::FrameAssembler(const AssemblerParams& params, WallClockNs wall_clock_ns)
    : params_(params), wall_clock_ns_(std::move(wall_clock_ns)) {
  params_.validate();
  if (!wall_clock_ns_) throw std::invalid_argument("assembler needs a wall clock");
}

void FrameAssembler::leaving(int64_t t_ns) {
  if (last_left_ns_ && t_ns <= *last_left_ns_) return;
  if (last_left_ns_ && params_.nominal_period_ns > 0) {
    const int64_t periods = (t_ns - *last_left_ns_ + params_.nominal_period_ns / 2) / params_.nominal_period_ns;
    if (periods > 1) counters_.frames_missing += static_cast<uint64_t>(periods - 1);
  }
  last_left_ns_ = t_ns;
}

void FrameAssembler::reject(const std::string& reason) {
  ++counters_.rejected_invalid;
  counters_.last_rejection = reason;
}

FrameAssembler::Pending* FrameAssembler::slot(int64_t t_ns, const char* what, const PartArrival& arrival) {
  ++counters_.parts_received;
  last_arrival_wall_ns_ = wall_clock_ns_();
  const int64_t arrived_ns = arrival.arrived_ns > 0 ? arrival.arrived_ns : last_arrival_wall_ns_;
  if (last_released_ns_ && t_ns <= *last_released_ns_) {
    reject(std::string(what) + " stamp " + std::to_string(t_ns) + " ns is not after the last assembled frame (" +
           std::to_string(*last_released_ns_) + " ns): stamps went backwards or the sample came too late");
    return nullptr;
  }
  auto it = pending_.find(t_ns);
  if (it == pending_.end()) {
    if (static_cast<int>(pending_.size()) >= params_.max_pending) {
      if (t_ns < pending_.begin()->first) {  // older than everything waiting: it is the one to drop
        ++counters_.dropped_queue_full;
        leaving(t_ns);
        return nullptr;
      }
      leaving(pending_.begin()->first);
      pending_.erase(pending_.begin());
      ++counters_.dropped_queue_full;
    }
    it = pending_.emplace(t_ns, Pending{}).first;
  }
  newest_ns_ = std::max(newest_ns_, t_ns);
  FrameTiming& timing = it->second.timing;
  if (timing.received_ns == 0 || arrived_ns < timing.received_ns) timing.received_ns = arrived_ns;
  timing.decode_ms += arrival.decode_ms;
  return &it->second;
}

void FrameAssembler::addColour(int64_t t_ns, const cv::Mat& image, const PartArrival& arrival) {
  if (Pending* p = slot(t_ns, "colour", arrival)) p->colour = image, boundPendingBytes();
}
void FrameAssembler::addDepth(int64_t t_ns, const cv::Mat& depth_m, const PartArrival& arrival) {
  if (Pending* p = slot(t_ns, "depth", arrival)) p->depth = depth_m, boundPendingBytes();
}
void FrameAssembler::addMask(int64_t t_ns, const cv::Mat& instance_ids, const PartArrival& arrival) {
  if (Pending* p = slot(t_ns, "mask", arrival)) p->mask = instance_ids, boundPendingBytes();
}

void FrameAssembler::boundPendingBytes() {
  auto bytes = [](const cv::Mat& m) { return m.empty() ? size_t{0} : m.total() * m.elemSize(); };
  auto set_bytes = [&](const Pending& p) {
    return bytes(p.colour) + bytes(p.depth) + bytes(p.mask) +
           (p.lidar ? p.lidar->points_camera.size() * sizeof(Eigen::Vector3f) : size_t{0});
  };
  size_t total = 0;
  for (const auto& [t, p] : pending_) total += set_bytes(p);
  // The oldest sets go first; the newest always stays (one set is what a frame needs).
  while (total > params_.max_pending_bytes && pending_.size() > 1) {
    total -= set_bytes(pending_.begin()->second);
    leaving(pending_.begin()->first);
    pending_.erase(pending_.begin());
    ++counters_.dropped_queue_full;
  }
}
void FrameAssembler::addLidar(int64_t t_ns, LidarPart scan, const PartArrival& arrival) {
  if (Pending* p = slot(t_ns, "LiDAR scan", arrival)) p->lidar = std::move(scan), boundPendingBytes();
}

void FrameAssembler::addOdometry(int64_t t_ns, const StampedPose& pose, const PartArrival& arrival) {
  if (!pose.T_odom_camera.translation().allFinite() || !pose.T_odom_camera.rotation().coeffs().allFinite() ||
      (pose.twist_sigma_per_s && (!pose.twist_sigma_per_s->allFinite() || (pose.twist_sigma_per_s->array() <= 0.0).any()))) {
    ++counters_.parts_received;
    reject("odometry at " + std::to_string(t_ns) + " ns is not finite or has non-positive sigmas");
    return;
  }
  if (Pending* p = slot(t_ns, "odometry", arrival)) p->pose = pose;
}

bool FrameAssembler::complete(const Pending& p) const {
  return !p.colour.empty() && !p.depth.empty() && (!params_.expect_mask || !p.mask.empty()) &&
         (!params_.expect_lidar || p.lidar.has_value()) && (!params_.expect_odometry || p.pose.has_value());
}

std::vector<ImageFrame> FrameAssembler::takeReady() {
  std::vector<ImageFrame> ready;
  const bool silent = wall_clock_ns_() - last_arrival_wall_ns_ >= params_.silence_timeout_ns;
  while (!pending_.empty()) {
    auto it = pending_.begin();
    if (!complete(it->second)) {
      // The oldest set waits for its missing parts (topics arrive in any order) until it times out;
      // later sets wait behind it so that frames leave in stamp order.
      if (!silent && newest_ns_ - it->first < params_.timeout_ns) break;
      leaving(it->first);
      pending_.erase(it);
      ++counters_.dropped_incomplete;
      continue;
    }
    leaving(it->first);
    ImageFrame frame;
    frame.frame_index = next_frame_index_++;
    frame.t_ns = it->first;
    frame.image = it->second.colour;
    frame.depth_m = it->second.depth;
    frame.instance_ids = it->second.mask;
    frame.timing = it->second.timing;
    if (it->second.lidar) {
      frame.lidar_points_camera = std::move(it->second.lidar->points_camera);
      frame.lidar_origin_camera = it->second.lidar->origin_camera;
      frame.lidar_up_camera = it->second.lidar->up_camera;
    }
    frame.timing.assembled_ns = wall_clock_ns_();
    if (it->second.pose) {
      if (last_released_pose_) {
        OdometryMeasurement odometry;
        odometry.T_prev_curr = last_released_pose_->T_odom_camera.inverse() * it->second.pose->T_odom_camera;
        const double dt_s = static_cast<double>(it->first - last_released_pose_ns_) * 1e-9;
        const auto& twist = it->second.pose->twist_sigma_per_s;
        odometry.sigma = twist && dt_s > 0.0 ? Vec6(*twist * dt_s) : params_.default_increment_sigma;
        frame.odometry = odometry;
      }
      last_released_pose_ = it->second.pose;
      last_released_pose_ns_ = it->first;
    }
    last_released_ns_ = it->first;
    pending_.erase(it);
    ++counters_.frames_assembled;
    ready.push_back(std::move(frame));
  }
  return ready;
}

}  // namespace dslam
