#pragma once
// The q-quantile (0..1, nearest rank) of a sample, for the benchmarks' tables.

#include <algorithm>
#include <vector>

namespace dslam::bench {

inline double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

}  // namespace dslam::bench
