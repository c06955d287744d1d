#include "plugin/estimate_stream_stats.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace dslam {

namespace {
constexpr size_t kRecentStamps = 4096;  // repeats are looked for among this many latest stamps
}

EstimateStreamStats::EstimateStreamStats(double frame_rate_hz) {
  if (!std::isfinite(frame_rate_hz) || frame_rate_hz <= 0.0)
    throw std::invalid_argument("frame rate must be positive, got " + std::to_string(frame_rate_hz));
  period_ns_ = 1e9 / frame_rate_hz;
}

double EstimateStreamStats::add(const ReceivedEstimate& e) {
  ++received_;
  ++per_writer_[e.writer];
  if (last_receipt_ns_ != 0)
    longest_silence_ms_ =
        std::max(longest_silence_ms_, static_cast<double>(e.received_unix_ns - last_receipt_ns_) * 1e-6);
  last_receipt_ns_ = e.received_unix_ns;

  if (recent_.count(e.stamp_ns)) {
    ++repeated_;
  } else {
    recent_.insert(e.stamp_ns);
    recent_order_.push_back(e.stamp_ns);
    if (recent_order_.size() > kRecentStamps) {
      recent_.erase(recent_order_.front());
      recent_order_.pop_front();
    }
    if (received_ - repeated_ > 1 && e.stamp_ns < newest_stamp_ns_) {
      ++went_back_;
    } else if (received_ - repeated_ > 1) {
      // Frames at the sensor's rate that should lie between the two stamps (half a period of jitter allowed).
      const double steps = std::round(static_cast<double>(e.stamp_ns - newest_stamp_ns_) / period_ns_);
      if (steps > 1.0) missing_ += static_cast<uint64_t>(steps - 1.0);
    }
    newest_stamp_ns_ = std::max(newest_stamp_ns_, e.stamp_ns);
  }

  const double latency_ms = static_cast<double>(e.received_unix_ns - e.stamp_ns) * 1e-6;
  if (std::abs(latency_ms) > 60e3) return -1.0;  // not a stamp of this host's clock
  latency_.add(std::max(latency_ms, 0.0));
  return latency_ms;
}

std::string EstimateStreamStats::line() const {
  std::ostringstream s;
  s << received_ << " estimates (" << distinctStamps() << " frames) from " << per_writer_.size()
    << (per_writer_.size() == 1 ? " writer" : " writers") << ", " << repeated_ << " repeated, " << went_back_
    << " out of order, " << missing_ << " missing between stamps";
  if (latency_.count() > 0) {
    s << std::fixed;
    s.precision(1);
    s << ", latency capture->receipt " << latency_.quantile(0.5) << "/" << latency_.quantile(0.99) << "/"
      << latency_.max() << " ms (median/p99/max)";
  }
  s.precision(0);
  s << std::fixed << ", longest silence " << longest_silence_ms_ << " ms";
  return s.str();
}

nlohmann::json EstimateStreamStats::json() const {
  nlohmann::json j;
  j["received"] = received_;
  j["frames"] = distinctStamps();
  j["repeated"] = repeated_;
  j["out_of_order"] = went_back_;
  j["missing_between_stamps"] = missing_;
  j["longest_silence_ms"] = longest_silence_ms_;
  j["writers"] = per_writer_;
  if (latency_.count() > 0)
    j["capture_to_receipt_ms"] = {{"frames", latency_.count()},
                                  {"median_ms", latency_.quantile(0.5)},
                                  {"p99_ms", latency_.quantile(0.99)},
                                  {"max_ms", latency_.max()}};
  return j;
}

}  // namespace dslam
