#include "pipeline/stage_latency.h"

#include <algorithm>
#include <cmath>

#include "output/text_format.h"

namespace dslam {
namespace {

constexpr double kFirstBinMs = 0.01;
const double kLogStep = std::log(1.01);

double NsToMs(int64_t from_ns, int64_t to_ns) { return 1e-6 * static_cast<double>(to_ns - from_ns); }

}  // namespace

void LatencyHistogram::add(double ms) {
  if (!std::isfinite(ms)) return;
  ms = std::max(ms, 0.0);
  const double position = ms > kFirstBinMs ? std::log(ms / kFirstBinMs) / kLogStep : 0.0;
  const int bin = std::min(kBins - 1, static_cast<int>(position));
  ++bins_[static_cast<size_t>(bin)];
  ++count_;
  max_ms_ = std::max(max_ms_, ms);
}

double LatencyHistogram::quantile(double q) const {
  if (count_ == 0) return 0.0;
  const auto rank = static_cast<uint64_t>(std::max(1.0, std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_))));
  uint64_t seen = 0;
  for (int bin = 0; bin < kBins; ++bin) {
    seen += bins_[static_cast<size_t>(bin)];
    if (seen >= rank) {
      if (bin == 0) return std::min(max_ms_, kFirstBinMs);
      return std::min(max_ms_, kFirstBinMs * std::exp((bin + 0.5) * kLogStep));  // the bin's middle
    }
  }
  return max_ms_;
}

const std::array<const char*, StageLatency::kStages>& StageLatency::StageNames() {
  static const std::array<const char*, kStages> names = {"input",   "decode",  "frontend_wait",
                                                          "frontend", "backend_wait", "backend",
                                                          "publish", "total",   "capture"};
  return names;
}

void StageLatency::add(const FrameTiming& t, double capture_to_published_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto span = [&](int stage, int64_t from_ns, int64_t to_ns) {
    if (from_ns > 0 && to_ns > 0) stages_[static_cast<size_t>(stage)].add(NsToMs(from_ns, to_ns));
  };
  span(0, t.received_ns, t.assembled_ns);
  if (t.decode_ms > 0.0) stages_[1].add(t.decode_ms);
  span(2, t.assembled_ns, t.frontend_start_ns);
  span(3, t.frontend_start_ns, t.frontend_end_ns);
  span(4, t.frontend_end_ns, t.backend_start_ns);
  span(5, t.backend_start_ns, t.backend_end_ns);
  span(6, t.backend_end_ns, t.published_ns);
  span(7, t.received_ns, t.published_ns);
  if (capture_to_published_ms >= 0.0) stages_[8].add(capture_to_published_ms);
}

std::vector<StageLatencySummary> StageLatency::summary() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<StageLatencySummary> out;
  for (int i = 0; i < kStages; ++i) {
    const LatencyHistogram& h = stages_[static_cast<size_t>(i)];
    if (h.count() == 0) continue;
    out.push_back({StageNames()[static_cast<size_t>(i)], h.count(), h.quantile(0.5), h.quantile(0.99), h.max()});
  }
  return out;
}

std::string FormatLatencyLine(const std::vector<StageLatencySummary>& stages) {
  std::string line;
  for (const StageLatencySummary& s : stages) {
    if (!line.empty()) line += ", ";
    line += s.stage + " " + FormatFixed(s.median_ms, 1, "-") + "/" + FormatFixed(s.p99_ms, 1, "-");
  }
  return line;
}

nlohmann::json LatencyJson(const std::vector<StageLatencySummary>& stages) {
  nlohmann::json out = nlohmann::json::object();
  for (const StageLatencySummary& s : stages)
    out[s.stage] = {{"frames", s.frames}, {"median_ms", s.median_ms}, {"p99_ms", s.p99_ms}, {"max_ms", s.max_ms}};
  return out;
}

}  // namespace dslam
