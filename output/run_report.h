#pragma once
// Result files of a run (metrics.json, trajectories, object motion and speed tables) and the
// console table, written from the methods' estimates and metrics.

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "backend/methods.h"
#include "data/sequence.h"
#include "evaluation/evaluate_run.h"

namespace dslam {

struct MethodOutcome {
  MethodResult result;
  MethodMetrics metrics;
};

using MethodOutcomes = std::map<Method, MethodOutcome>;

// The metrics.json object of one method (keys fixed by the schema; null where absent).
nlohmann::json MethodMetricsJson(const MethodMetrics& metrics, double wall_time_s);

// metrics.json: each method's metrics and wall time, and the run's record.
void WriteMetricsJson(const std::string& dir, const MethodOutcomes& outcomes, const nlohmann::json& run_info);
// camera_gt.{tum,kitti} (when there are poses; stamps per frame) and object_centroids_gt.csv.
void WriteGroundTruthFiles(const std::string& dir, const GroundTruth& gt, const std::vector<int64_t>& t_ns);

// Writes into `dir` (created if needed): metrics.json, camera_{gt,ours,static_only,slam_mot}.{tum,kitti} (gt
// only when the sequence has ground truth), camera_ours_online.tum (each frame's pose as it stood right after
// that frame, when the run recorded it),
// object_motions.csv and object_speeds.csv (ours), object_motions_slam_mot.csv, object_speeds_slam_mot.csv,
// object_centroids_gt.csv (frame,object_id,category,observed,x,y,z) and map_points.csv (ours:
// frame,object_id,x,y,z; static landmarks once with frame -1 and object_id -1) and objects.csv (ours, one
// row per object, see output/object_summary.h).
void WriteRunOutputs(const std::string& dir, const Sequence& seq, const MethodOutcomes& outcomes,
                     const nlohmann::json& run_info);

// Rows = metrics, columns = static-only, SLAM+MOT, ours (as the paper's Table I).
std::string FormatMetricsTable(const MethodOutcomes& outcomes, const std::string& title);

}  // namespace dslam
