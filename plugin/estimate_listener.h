#pragma once
// Listens to a vehicle's camera estimates (rt/.../dslam/camera_odometry) and records when each stamp's
// estimate arrived and which writer sent it: for latency measurements, `dslam listen`, and the network
// tests (a hot standby's estimates come from another writer). No Fast DDS type appears in this header.

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "geometry/se3.h"

namespace dslam {

// One camera estimate as a subscriber receives it.
struct ReceivedEstimate {
  int64_t stamp_ns = 0;          // the frame's header stamp
  int64_t received_unix_ns = 0;  // the system clock when it arrived
  std::string writer;            // the DDS writer that sent it: its GUID, 32 hex digits
  SE3 T_world_camera;
};

class CameraEstimateListener {
 public:
  using Clock = std::chrono::steady_clock;
  using Callback = std::function<void(const ReceivedEstimate&)>;
  // `on_estimate` (optional) is called on Fast DDS' receive thread for every estimate, in arrival order.
  // Throws std::runtime_error when the participant or the reader cannot be created.
  CameraEstimateListener(int domain_id, const std::string& profiles_file, const std::string& vehicle,
                         Callback on_estimate = {});
  ~CameraEstimateListener();
  CameraEstimateListener(const CameraEstimateListener&) = delete;
  CameraEstimateListener& operator=(const CameraEstimateListener&) = delete;

  // Stamp (ns) -> when its estimate arrived; a copy, taken under the listener's lock.
  std::map<int64_t, Clock::time_point> receipts() const;
  // Writers the reader is matched with now (a standby counts while it is alive).
  int matchedWriters() const;
  // Writers whose liveliness the reader holds now (-1 before the first change): a writer whose host died
  // leaves this count when its lease expires, and may still be matched until discovery notices.
  int aliveWriters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dslam
