#pragma once
// Listens to a vehicle's camera estimates (rt/.../dslam/camera_odometry) and records when each stamp's
// estimate arrived: for latency measurements. No Fast DDS type appears in this header.

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

namespace dslam {

class CameraEstimateListener {
 public:
  using Clock = std::chrono::steady_clock;
  // Throws std::runtime_error when the participant or the reader cannot be created.
  CameraEstimateListener(int domain_id, const std::string& profiles_file, const std::string& vehicle);
  ~CameraEstimateListener();
  CameraEstimateListener(const CameraEstimateListener&) = delete;
  CameraEstimateListener& operator=(const CameraEstimateListener&) = delete;

  // Stamp (ns) -> when its estimate arrived; a copy, taken under the listener's lock.
  std::map<int64_t, Clock::time_point> receipts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dslam
