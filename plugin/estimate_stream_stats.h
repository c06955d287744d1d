#pragma once
// What a subscriber can say about the estimates it received: how many, from which writers, repeated
// stamps (two servers both publishing), stamps that went back, frames missing between stamps at the
// sensor's rate, the longest silence between receipts (a failover's gap), and the latency from each
// frame's capture stamp to its receipt. Bounded memory: it can run for hours. No DDS here.

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <unordered_set>

#include <nlohmann/json.hpp>

#include "pipeline/stage_latency.h"
#include "plugin/estimate_listener.h"

namespace dslam {

class EstimateStreamStats {
 public:
  // `frame_rate_hz`: the sensor's rate, to count frames missing between consecutive stamps.
  explicit EstimateStreamStats(double frame_rate_hz);

  // Returns the capture-to-receipt latency in ms, or a negative value when the stamp is not of this
  // host's clock (more than a minute away from the receipt).
  double add(const ReceivedEstimate& estimate);

  uint64_t received() const { return received_; }
  uint64_t distinctStamps() const { return received_ - repeated_; }
  uint64_t repeated() const { return repeated_; }      // a stamp already received (within the last 4096)
  uint64_t wentBack() const { return went_back_; }     // a new stamp older than the newest one
  uint64_t missingFrames() const { return missing_; }  // frames at the rate between consecutive new stamps
  double longestSilenceMs() const { return longest_silence_ms_; }
  const std::map<std::string, uint64_t>& perWriter() const { return per_writer_; }
  const LatencyHistogram& captureLatency() const { return latency_; }

  // "120 estimates from 1 writer, 0 repeated, 0 missing, latency capture->receipt 35.1/80.2 ms (median/p99),
  // longest silence 120 ms"
  std::string line() const;
  nlohmann::json json() const;

 private:
  double period_ns_;
  uint64_t received_ = 0, repeated_ = 0, went_back_ = 0, missing_ = 0;
  int64_t newest_stamp_ns_ = 0, last_receipt_ns_ = 0;
  double longest_silence_ms_ = 0.0;
  std::map<std::string, uint64_t> per_writer_;
  std::deque<int64_t> recent_order_;
  std::unordered_set<int64_t> recent_;
  LatencyHistogram latency_;
};

}  // namespace dslam
