#pragma once
// Per-object results of a run: objects.csv and a console table like the paper's Table II.

#include <string>
#include <vector>

#include "backend/estimate.h"
#include "data/sequence.h"
#include "evaluation/metrics.h"

namespace dslam {

struct ObjectSummary {
  int object_id = 0;
  std::string category;
  int gt_pairs = 0;
  int frames_estimated = 0;
  ObjectMetrics metrics;
  std::optional<double> mean_gt_speed_kmh;   // over estimated frame pairs
  std::optional<double> mean_est_speed_kmh;
};

// One summary per ground-truth object that was observed in two consecutive frames at least.
std::vector<ObjectSummary> SummariseObjects(const Sequence& seq, const Estimate& est);

// objects.csv: id, category, frames estimated, OMTE, OMRE, OMSE, mean gt and estimated speed (km/h).
void WriteObjectsCsv(const std::string& path, const std::vector<ObjectSummary>& objects);
std::string FormatObjectTable(const std::vector<ObjectSummary>& objects, const std::string& title);

}  // namespace dslam
