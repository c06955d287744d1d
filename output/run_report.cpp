#include "output/run_report.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

#include "output/object_rows.h"
#include "output/object_summary.h"
#include "output/text_format.h"
#include "output/trajectory_io.h"
#include "output/whole_file.h"

namespace dslam {
namespace {
nlohmann::json Opt(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }

WholeFile OpenCsv(const std::string& path, const std::string& header) {
  WholeFile out(path);
  out << std::setprecision(9) << header << '\n';
  return out;
}

// Rows for every ground-truth pair (estimate blank when missing), then every estimate without one. When the
// run's object ids are its own (GroundTruth::run_object_ids), a row carries the run's id and the ground truth
// of the object it was found to be over that pair; pairs the run has no estimate of are left out.
void WriteObjectTables(const std::string& dir, const std::string& suffix, const Sequence& seq, const Estimate& est) {
  std::map<std::pair<int, int>, const ObjectMotionEstimate*> by_key;
  for (const auto& m : est.object_motions) by_key[{m.object_id, m.frame}] = &m;
  WholeFile motions = OpenCsv(dir + "/object_motions" + suffix + ".csv", kObjectMotionsHeader);
  WholeFile speeds = OpenCsv(dir + "/object_speeds" + suffix + ".csv", kObjectSpeedsHeader);
  const bool own_ids = seq.gt.run_object_ids.has_value();
  for (const auto& [id, obj] : seq.gt.objects)
    for (int k : obj.observed_frames) {
      const std::optional<ObjectPairSample> gt = GroundTruthPair(seq.gt, seq.frame_rate_hz, id, k);
      if (!gt) continue;
      const int run_id = RunObjectId(seq.gt, id, k);
      const auto it = by_key.find({run_id, k});
      if (own_ids && it == by_key.end()) continue;
      PutObjectRows(motions, speeds, own_ids ? run_id : id, k, it == by_key.end() ? nullptr : it->second, &*gt);
      if (it != by_key.end()) by_key.erase(it);
    }
  for (const auto& [key, m] : by_key) PutObjectRows(motions, speeds, key.first, key.second, m, nullptr);
  motions.commit();
  speeds.commit();
}

void WriteGroundTruthCentroids(const std::string& path, const GroundTruth& gt) {
  WholeFile out = OpenCsv(path, "frame,object_id,category,observed,x,y,z");
  for (const auto& [id, obj] : gt.objects)
    for (const auto& [k, c] : obj.centroid_world)
      out << k << ',' << id << ',' << obj.category << ',' << obj.observed_frames.count(k) << ',' << c.x() << ','
          << c.y() << ',' << c.z() << '\n';
  out.commit();
}

void WriteMapPoints(const std::string& path, const Estimate& est) {
  // Static structure once per landmark (its final estimate); dynamic points once per observation.
  WholeFile out = OpenCsv(path, "frame,object_id,x,y,z");
  // A landmark's observations arrive oldest first (a streaming smoother emits each as its frame leaves the
  // window): its last one carries the final estimate.
  std::map<int64_t, size_t> last_static;
  for (size_t i = 0; i < est.points.size(); ++i)
    if (est.points[i].object_id < 0) last_static[est.points[i].track_id] = i;
  for (size_t i = 0; i < est.points.size(); ++i) {
    const PointEstimate& p = est.points[i];
    if (p.object_id < 0 && last_static.at(p.track_id) != i) continue;
    out << (p.object_id < 0 ? -1 : p.frame) << ',' << p.object_id << ',' << p.p_world.x() << ',' << p.p_world.y() << ','
        << p.p_world.z() << '\n';
  }
  out.commit();
}

}  // namespace

nlohmann::json MethodMetricsJson(const MethodMetrics& m, double wall_time_s) {
  nlohmann::json j;
  j["rte_pct"] = Opt(m.camera.rte_pct);
  j["rre_deg_per_m"] = Opt(m.camera.rre_deg_per_m);
  j["rse_pct"] = Opt(m.rse_pct);
  const ObjectMetrics* o = m.objects ? &*m.objects : nullptr;
  j["omte_pct"] = Opt(o ? o->omte_pct : std::nullopt);
  j["omre_deg_per_m"] = Opt(o ? o->omre_deg_per_m : std::nullopt);
  j["omse_pct"] = Opt(o ? o->omse_pct : std::nullopt);
  j["ate_m"] = m.camera.ate_m;
  j["me_t_m"] = Opt(o ? o->me_t_m : std::nullopt);
  j["me_r_deg"] = Opt(o ? o->me_r_deg : std::nullopt);
  j["speed_err_mps"] = Opt(o ? o->speed_err_mps : std::nullopt);
  j["object_coverage"] = Opt(o ? o->object_coverage : std::nullopt);
  j["object_coverage_measurable"] = Opt(o ? o->object_coverage_measurable : std::nullopt);
  j["motion_nees"] = Opt(o ? o->motion_nees : std::nullopt);
  // Beyond the fixed schema: context a reader needs to interpret the figures above.
  j["speed_err_kmh"] = Opt(o && o->speed_err_mps ? std::optional<double>(*o->speed_err_mps * 3.6) : std::nullopt);
  j["camera_path_m"] = m.camera.path_length_m;
  j["camera_step_nees"] = Opt(m.camera.camera_step_nees);
  j["mean_step_te_m"] = Opt(m.camera.mean_step_te_m);
  j["mean_step_re_deg"] = Opt(m.camera.mean_step_re_deg);
  j["static_pairs_mean_speed_mps"] = Opt(o ? o->static_mean_speed_mps : std::nullopt);
  j["static_pairs_false_dynamic_frac"] = Opt(o ? o->static_false_dynamic_frac : std::nullopt);
  j["object_gt_pairs"] = o ? nlohmann::json(o->gt_pairs) : nlohmann::json(nullptr);
  j["object_gt_moving_pairs"] = o ? nlohmann::json(o->gt_moving_pairs) : nlohmann::json(nullptr);
  j["object_moving_pairs_estimated"] = o ? nlohmann::json(o->moving_pairs_estimated) : nlohmann::json(nullptr);
  j["wall_time_s"] = wall_time_s;
  return j;
}

void WriteMetricsJson(const std::string& dir, const MethodOutcomes& outcomes, const nlohmann::json& run_info) {
  nlohmann::json metrics;
  for (const auto& [method, outcome] : outcomes)
    metrics["methods"][ToString(method)] = MethodMetricsJson(outcome.metrics, outcome.result.wall_time_s);
  metrics["run"] = run_info;
  WholeFile out(dir + "/metrics.json");
  out << metrics.dump(2) << '\n';
  out.commit();
}

void WriteGroundTruthFiles(const std::string& dir, const GroundTruth& gt, const std::vector<int64_t>& t_ns) {
  WriteGroundTruthCentroids(dir + "/object_centroids_gt.csv", gt);
  if (!gt.T_world_camera.empty()) {  // a recording without ground truth has none to write
    WriteTumTrajectory(dir + "/camera_gt.tum", t_ns, gt.T_world_camera);
    WriteKittiTrajectory(dir + "/camera_gt.kitti", gt.T_world_camera);
  }
}

void WriteRunOutputs(const std::string& dir, const Sequence& seq, const MethodOutcomes& outcomes,
                     const nlohmann::json& run_info) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create output directory " + dir + ": " + ec.message());

  WriteMetricsJson(dir, outcomes, run_info);
  std::vector<int64_t> t_ns;
  for (const auto& f : seq.frames) t_ns.push_back(f.t_ns);
  WriteGroundTruthFiles(dir, seq.gt, t_ns);
  for (const auto& [method, outcome] : outcomes) {
    WriteTumTrajectory(dir + "/camera_" + ToString(method) + ".tum", t_ns, outcome.result.estimate.T_world_camera);
    WriteKittiTrajectory(dir + "/camera_" + ToString(method) + ".kitti", outcome.result.estimate.T_world_camera);
    if (method == Method::kOurs) {
      if (!outcome.result.online.empty()) {  // what an online run knew at each frame
        std::vector<int64_t> online_t_ns;
        std::vector<SE3> online_poses;
        for (const FrameEstimate& e : outcome.result.online) online_t_ns.push_back(e.t_ns), online_poses.push_back(e.T_world_camera);
        WriteTumTrajectory(dir + "/camera_ours_online.tum", online_t_ns, online_poses);
      }
      WriteObjectTables(dir, "", seq, outcome.result.estimate);
      WriteMapPoints(dir + "/map_points.csv", outcome.result.estimate);
      WriteObjectsCsv(dir + "/objects.csv", SummariseObjects(seq, outcome.result.estimate));
    }
    if (method == Method::kSlamMot) WriteObjectTables(dir, "_slam_mot", seq, outcome.result.estimate);
  }
}

std::string FormatMetricsTable(const MethodOutcomes& outcomes, const std::string& title) {
  struct Row {
    const char* label;
    std::function<std::optional<double>(const MethodMetrics&)> get;
    int precision;
  };
  auto obj = [](auto field) {
    return [field](const MethodMetrics& m) -> std::optional<double> {
      return m.objects ? (*m.objects).*field : std::nullopt;
    };
  };
  const std::vector<Row> rows = {
      {"Camera RTE (%)", [](const MethodMetrics& m) { return m.camera.rte_pct; }, 3},
      {"Camera RRE (deg/m)", [](const MethodMetrics& m) { return m.camera.rre_deg_per_m; }, 4},
      {"Camera ATE (m)", [](const MethodMetrics& m) { return std::optional<double>(m.camera.ate_m); }, 3},
      {"Structure RSE (%)", [](const MethodMetrics& m) { return m.rse_pct; }, 3},
      {"Object OMTE (%)", obj(&ObjectMetrics::omte_pct), 3},
      {"Object OMRE (deg/m)", obj(&ObjectMetrics::omre_deg_per_m), 4},
      {"Object OMSE (%)", obj(&ObjectMetrics::omse_pct), 3},
      {"Object ME_t (m)", obj(&ObjectMetrics::me_t_m), 4},
      {"Object ME_r (deg)", obj(&ObjectMetrics::me_r_deg), 4},
      {"Speed error (m/s)", obj(&ObjectMetrics::speed_err_mps), 3},
      {"Object coverage", obj(&ObjectMetrics::object_coverage), 3},
      {"  of measurable pairs", obj(&ObjectMetrics::object_coverage_measurable), 3},
  };
  const std::vector<Method> columns = {Method::kStaticOnly, Method::kSlamMot, Method::kOurs};
  std::ostringstream out;
  out << title << '\n';
  char buf[128];
  std::snprintf(buf, sizeof buf, "%-22s %14s %14s %14s\n", "metric", "static-only", "SLAM+MOT", "ours");
  out << buf;
  for (const auto& row : rows) {
    std::string cells[3];
    for (int c = 0; c < 3; ++c) {
      const auto it = outcomes.find(columns[c]);
      cells[c] = it == outcomes.end() ? "-" : FormatFixed(row.get(it->second.metrics), row.precision, "-");
    }
    std::snprintf(buf, sizeof buf, "%-22s %14s %14s %14s\n", row.label, cells[0].c_str(), cells[1].c_str(),
                  cells[2].c_str());
    out << buf;
  }
  return out.str();
}

}  // namespace dslam
