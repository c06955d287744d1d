#pragma once
// The latency budget of an online pipeline: from each frame's FrameTiming, the median, p99 and maximum
// of every stage, in bounded memory (log-spaced bins 1 % wide), so that a service running for hours
// reports it as it goes. Thread-safe: the back-end thread adds frames, any thread reads summaries.
//
// Stages, in pipeline order (each from one recorded time to the next):
//   input          first part received (serve) or reading begun (run) -> the whole frame handed on
//   decode         decoding its parts (serve; part of input)
//   frontend_wait  waiting in the front-end's queue
//   frontend       the image front-end
//   backend_wait   waiting in the back-end's queue
//   backend        classifier and sliding-window smoother
//   publish        writing the estimate (serve) or handing it on (run)
//   total          input received -> estimate published
//   capture        capture stamp -> estimate published, on this host's clock (serve, when the stamps
//                  are of this host's clock: a driver on this host or a synchronised one)

#include <array>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "data/frame_timing.h"

namespace dslam {

struct StageLatencySummary {
  std::string stage;
  uint64_t frames = 0;
  double median_ms = 0.0, p99_ms = 0.0, max_ms = 0.0;
};

// Durations in ms, 0.01 ms to 10 minutes in bins 1 % wide (quantiles within 0.5 %); the maximum exact.
class LatencyHistogram {
 public:
  void add(double ms);
  uint64_t count() const { return count_; }
  double max() const { return max_ms_; }
  double quantile(double q) const;  // nearest rank, 0 <= q <= 1; 0 without samples

 private:
  static constexpr int kBins = 1800;
  std::array<uint64_t, kBins> bins_{};
  uint64_t count_ = 0;
  double max_ms_ = 0.0;
};

class StageLatency {
 public:
  static constexpr int kStages = 9;
  static const std::array<const char*, kStages>& StageNames();

  // `capture_to_published_ms` < 0: unknown (not recorded).
  void add(const FrameTiming& timing, double capture_to_published_ms = -1.0);
  // The stages with at least one frame, in pipeline order.
  std::vector<StageLatencySummary> summary() const;

 private:
  mutable std::mutex mutex_;
  std::array<LatencyHistogram, kStages> stages_;
};

// "frontend 31.2/45.0, backend 15.1/30.2, ..." (median/p99 ms per stage).
std::string FormatLatencyLine(const std::vector<StageLatencySummary>& stages);
// {"frontend": {"frames": n, "median_ms": .., "p99_ms": .., "max_ms": ..}, ...}
nlohmann::json LatencyJson(const std::vector<StageLatencySummary>& stages);

}  // namespace dslam
