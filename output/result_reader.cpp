#include "output/result_reader.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "data/text_parsing.h"
#include "output/trajectory_io.h"

namespace dslam {
namespace {
std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string f;
  while (std::getline(in, f, ',')) fields.push_back(f);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

SE3 PoseFrom(const std::vector<std::string>& row, int first, const std::string& path, int line) {
  double v[7];
  for (int i = 0; i < 7; ++i) v[i] = ParseDouble(row[first + i], path, line, "pose field");
  return SE3(Eigen::Quaterniond(v[6], v[3], v[4], v[5]), Vec3(v[0], v[1], v[2]));
}
}  // namespace

int CsvTable::column(const std::string& name, const std::string& path) const {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return static_cast<int>(i);
  throw std::runtime_error(path + ": no column '" + name + "'");
}

CsvTable ReadCsv(const std::string& path) {
  std::ifstream in = OpenText(path);
  CsvTable table;
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(path + ": empty file");
  table.header = SplitCsv(line);
  for (int line_no = 2; std::getline(in, line); ++line_no) {
    if (line.empty()) continue;
    auto fields = SplitCsv(line);
    if (fields.size() != table.header.size())
      throw std::runtime_error(AtLine(path, line_no, "expected " + std::to_string(table.header.size()) +
                                                         " fields, found " + std::to_string(fields.size())));
    table.rows.push_back(std::move(fields));
    table.line_numbers.push_back(line_no);
  }
  return table;
}

CsvTable ReadCsv(const std::string& path, const std::vector<std::string>& columns) {
  CsvTable table = ReadCsv(path);
  bool match = table.header.size() >= columns.size();
  for (size_t i = 0; match && i < columns.size(); ++i) match = table.header[i] == columns[i];
  if (!match) {
    std::string expected, found;
    for (const auto& c : columns) expected += (expected.empty() ? "" : ",") + c;
    for (const auto& c : table.header) found += (found.empty() ? "" : ",") + c;
    throw std::runtime_error(path + ": expected the columns " + expected + ", found " + found);
  }
  return table;
}

std::string RunResults::title() const {
  const auto& run = metrics.contains("run") ? metrics["run"] : nlohmann::json::object();
  std::string t = run.value("command", std::string("run"));
  if (run.contains("scenario")) t += " " + run["scenario"].get<std::string>();
  if (run.contains("sequence")) t += " " + run["sequence"].get<std::string>();
  t += ", " + method;
  if (run.contains("mode")) t += " (" + run["mode"].get<std::string>() + " motion)";
  return t;
}

RunResults ReadRunResults(const std::string& dir) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir)) throw std::runtime_error("results directory " + dir + " does not exist");
  RunResults r;
  r.dir = dir;
  {
    const std::string path = dir + "/metrics.json";
    std::ifstream in = OpenText(path);
    try {
      r.metrics = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
      throw std::runtime_error(path + ": not valid JSON: " + e.what());
    }
  }
  // The figures show ours; a run of other methods only (`run --methods static_only`) shows the first it has.
  for (const char* method : {"ours", "slam_mot", "static_only"})
    if (fs::exists(dir + "/camera_" + method + ".tum")) {
      r.method = method;
      break;
    }
  if (r.method.empty()) throw std::runtime_error(dir + ": no camera_ours.tum, camera_slam_mot.tum or camera_static_only.tum");
  const std::string camera_path = dir + "/camera_" + r.method + ".tum";
  r.has_ground_truth = fs::exists(dir + "/camera_gt.tum");
  if (r.has_ground_truth) {
    r.camera_gt = ReadTumTrajectory(dir + "/camera_gt.tum", &r.t_ns);
    r.camera_est = ReadTumTrajectory(camera_path);
  } else {
    r.camera_est = ReadTumTrajectory(camera_path, &r.t_ns);
  }
  if (r.has_ground_truth && r.camera_est.size() != r.camera_gt.size())
    throw std::runtime_error(camera_path + ": " + std::to_string(r.camera_est.size()) + " poses for " +
                             std::to_string(r.camera_gt.size()) + " in camera_gt.tum");

  // Ours always writes its object and map files (object_speeds.csv, ...); SLAM+MOT its object files with
  // its name (object_speeds_slam_mot.csv, ...); static-only none.
  const std::string suffix = r.method == "ours" ? "" : "_" + r.method;
  const std::string speeds_path = dir + "/object_speeds" + suffix + ".csv";
  r.has_objects = r.method == "ours" || fs::exists(speeds_path);
  const CsvTable speeds = !r.has_objects ? CsvTable{} :
      ReadCsv(speeds_path, {"frame", "object_id", "is_dynamic", "est_speed_mps", "gt_speed_mps"});
  std::optional<size_t> sigma_column;
  if (speeds.header.size() > 5 && speeds.header[5] == "speed_sigma_mps") sigma_column = 5;
  // The centroid and box columns, in files that have them (written since they were added).
  std::optional<size_t> centroid_column, box_column;
  const auto at = std::find(speeds.header.begin(), speeds.header.end(), "centroid_x_m");
  if (at != speeds.header.end() && speeds.header.end() - at >= 3) centroid_column = static_cast<size_t>(at - speeds.header.begin());
  const auto box_at = std::find(speeds.header.begin(), speeds.header.end(), "box_x");
  if (box_at != speeds.header.end() && speeds.header.end() - box_at >= 4) box_column = static_cast<size_t>(box_at - speeds.header.begin());
  for (size_t i = 0; i < speeds.rows.size(); ++i) {
    const auto& row = speeds.rows[i];
    const int line = speeds.line_numbers[i];
    RunResults::SpeedRow s;
    s.frame = ParseInt(row[0], speeds_path, line, "frame");
    s.object_id = ParseInt(row[1], speeds_path, line, "object id");
    s.estimated = !row[3].empty();
    s.is_dynamic = row[2] == "1";
    if (s.estimated) s.est_mps = ParseDouble(row[3], speeds_path, line, "estimated speed");
    if (sigma_column && !row[*sigma_column].empty())
      s.sigma_mps = ParseDouble(row[*sigma_column], speeds_path, line, "speed sigma");
    if (centroid_column && !row[*centroid_column].empty()) {
      Vec3 c;
      for (int a = 0; a < 3; ++a) c[a] = ParseDouble(row[*centroid_column + a], speeds_path, line, "centroid");
      s.centroid_camera = c;
    }
    if (box_column && !row[*box_column].empty()) {
      std::array<int, 4> b{};
      for (int a = 0; a < 4; ++a) b[a] = ParseInt(row[*box_column + a], speeds_path, line, "image box");
      s.box = b;
    }
    if (!r.has_ground_truth) {
      if (s.estimated) r.speeds.push_back(s);
      continue;
    }
    if (row[4].empty()) continue;  // estimate without a ground-truth pair
    s.gt_mps = ParseDouble(row[4], speeds_path, line, "ground-truth speed");
    r.speeds.push_back(s);
  }

  const std::string motions_path = dir + "/object_motions" + suffix + ".csv";
  const CsvTable motions = !r.has_objects && !fs::exists(motions_path) ? CsvTable{} :
      ReadCsv(motions_path, {"frame", "object_id", "is_dynamic", "est_tx", "est_ty", "est_tz", "est_qx", "est_qy",
                             "est_qz", "est_qw", "gt_tx", "gt_ty", "gt_tz", "gt_qx", "gt_qy", "gt_qz", "gt_qw"});
  for (size_t i = 0; i < motions.rows.size(); ++i) {
    const auto& row = motions.rows[i];
    const int line = motions.line_numbers[i];
    if (row[10].empty()) continue;  // no ground truth
    RunResults::MotionRow m;
    m.frame = ParseInt(row[0], motions_path, line, "frame");
    m.object_id = ParseInt(row[1], motions_path, line, "object id");
    m.estimated = !row[3].empty();
    if (m.estimated) m.H_est = PoseFrom(row, 3, motions_path, line);
    m.H_gt = PoseFrom(row, 10, motions_path, line);
    r.motions.push_back(m);
  }

  const std::string centroids_path = dir + "/object_centroids_gt.csv";
  const CsvTable centroids = !r.has_ground_truth && !fs::exists(centroids_path) ? CsvTable{} :
      ReadCsv(centroids_path, {"frame", "object_id", "category", "observed", "x", "y", "z"});
  for (size_t i = 0; i < centroids.rows.size(); ++i) {
    const auto& row = centroids.rows[i];
    const int line = centroids.line_numbers[i];
    RunResults::CentroidRow c;
    c.frame = ParseInt(row[0], centroids_path, line, "frame");
    c.object_id = ParseInt(row[1], centroids_path, line, "object id");
    c.category = row[2];
    c.observed = row[3] == "1";
    c.c_world = Vec3(ParseDouble(row[4], centroids_path, line, "x"), ParseDouble(row[5], centroids_path, line, "y"),
                     ParseDouble(row[6], centroids_path, line, "z"));
    r.centroids.push_back(c);
  }

  const std::string map_path = dir + "/map_points.csv";
  const CsvTable map = r.method != "ours" && !fs::exists(map_path) ? CsvTable{} :
      ReadCsv(map_path, {"frame", "object_id", "x", "y", "z"});
  for (size_t i = 0; i < map.rows.size(); ++i) {
    const auto& row = map.rows[i];
    const int line = map.line_numbers[i];
    r.map_points.push_back({ParseInt(row[0], map_path, line, "frame"), ParseInt(row[1], map_path, line, "object id"),
                            Vec3(ParseDouble(row[2], map_path, line, "x"), ParseDouble(row[3], map_path, line, "y"),
                                 ParseDouble(row[4], map_path, line, "z"))});
  }

  if (fs::exists(dir + "/objects.csv")) {
    const CsvTable objects = ReadCsv(dir + "/objects.csv");
    r.objects_header = objects.header;
    r.objects_rows = objects.rows;
  }
  return r;
}

}  // namespace dslam
