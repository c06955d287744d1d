#pragma once
// Checks that a streamed run (methods in lockstep, evaluation by sums, files written as the estimates
// become final) equals the collected run (RunSequence, then WriteRunOutputs): metrics to rounding,
// trajectories line for line, tables as sets of rows.

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "output/result_reader.h"
#include "output/run_report.h"
#include "output/trajectory_io.h"

namespace dslam::test {

inline void ExpectNearOpt(const std::optional<double>& streamed, const std::optional<double>& collected,
                          const std::string& what) {
  ASSERT_EQ(streamed.has_value(), collected.has_value()) << what;
  if (streamed) {
    EXPECT_NEAR(*streamed, *collected, 1e-9 * std::max(1.0, std::abs(*collected))) << what;
  }
}

// `objects_estimated`: the collected run estimated at least one object pair (an assertion on the scene).
inline void ExpectSameMetrics(const MethodMetrics& streamed, const MethodMetrics& collected, const std::string& what,
                              bool objects_estimated = true) {
  ExpectNearOpt(streamed.camera.rte_pct, collected.camera.rte_pct, what + " RTE");
  ExpectNearOpt(streamed.camera.rre_deg_per_m, collected.camera.rre_deg_per_m, what + " RRE");
  ExpectNearOpt(streamed.camera.ate_m, collected.camera.ate_m, what + " ATE");
  ExpectNearOpt(streamed.camera.camera_step_nees, collected.camera.camera_step_nees, what + " camera NEES");
  ExpectNearOpt(streamed.rse_pct, collected.rse_pct, what + " RSE");
  ASSERT_EQ(streamed.objects.has_value(), collected.objects.has_value()) << what;
  if (!collected.objects) return;
  const ObjectMetrics &s = *streamed.objects, &c = *collected.objects;
  EXPECT_EQ(s.gt_pairs, c.gt_pairs) << what;
  EXPECT_EQ(s.estimated_pairs, c.estimated_pairs) << what;
  if (objects_estimated) {
    EXPECT_GT(c.estimated_pairs, 0) << what;
  }
  ExpectNearOpt(s.omte_pct, c.omte_pct, what + " OMTE");
  ExpectNearOpt(s.omse_pct, c.omse_pct, what + " OMSE");
  ExpectNearOpt(s.object_coverage, c.object_coverage, what + " coverage");
  ExpectNearOpt(s.static_mean_speed_mps, c.static_mean_speed_mps, what + " static speed");
}

inline void ExpectSameTrajectory(const std::string& a_path, const std::string& b_path) {
  std::vector<int64_t> t_a, t_b;
  const auto a = ReadTumTrajectory(a_path, &t_a);
  const auto b = ReadTumTrajectory(b_path, &t_b);
  ASSERT_EQ(a.size(), b.size()) << a_path;
  EXPECT_EQ(t_a, t_b) << a_path;
  for (size_t k = 0; k < a.size(); ++k) ASSERT_LT((a[k].translation() - b[k].translation()).norm(), 1e-6) << a_path << " " << k;
}

// The same rows in any order; `non_empty`: the table must have rows.
inline void ExpectSameRows(const std::string& a_path, const std::string& b_path, bool non_empty = true) {
  const CsvTable a = ReadCsv(a_path), b = ReadCsv(b_path);
  EXPECT_EQ(a.header, b.header) << a_path;
  EXPECT_EQ(std::multiset<std::vector<std::string>>(a.rows.begin(), a.rows.end()),
            std::multiset<std::vector<std::string>>(b.rows.begin(), b.rows.end()))
      << a_path;
  if (non_empty) {
    EXPECT_FALSE(a.rows.empty()) << a_path;
  }
}

}  // namespace dslam::test
