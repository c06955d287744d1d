#pragma once
// Reads back the result files a run wrote (see output/run_report.h), for figures and reports.
// Errors throw std::runtime_error naming the file and line.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/se3.h"

namespace dslam {

struct RunResults {
  std::string dir;
  nlohmann::json metrics;
  std::vector<int64_t> t_ns;
  // False for a run on data without ground truth (a recording, `serve`): camera_gt, the centroids and the
  // motions' ground truth are empty, and speeds hold the estimates alone.
  bool has_ground_truth = true;
  // The method drawn: "ours", or for a run without it the first of slam_mot, static_only it has.
  std::string method;
  bool has_objects = true;  // object estimates (speeds, motions): ours always; static-only never
  std::vector<SE3> camera_gt, camera_est;  // of `method`
  struct SpeedRow {
    int frame = 0, object_id = 0;
    bool estimated = false, is_dynamic = false;
    double est_mps = 0.0, gt_mps = 0.0;
    double sigma_mps = 0.0;  // of the estimate; 0 when unknown (or written before the column existed)
    std::optional<Vec3> centroid_camera;  // where the object is in the frame's camera, when written
    std::optional<std::array<int, 4>> box;  // x, y, width, height in the image, when written
  };
  std::vector<SpeedRow> speeds;
  struct MotionRow {
    int frame = 0, object_id = 0;
    bool estimated = false;
    SE3 H_est, H_gt;
  };
  std::vector<MotionRow> motions;  // ground-truth pairs only
  struct CentroidRow {
    int frame = 0, object_id = 0;
    std::string category;
    bool observed = false;
    Vec3 c_world = Vec3::Zero();
  };
  std::vector<CentroidRow> centroids;
  struct MapPoint {
    int frame = -1, object_id = -1;
    Vec3 p_world = Vec3::Zero();
  };
  std::vector<MapPoint> map_points;
  std::vector<std::string> objects_header;              // objects.csv when present
  std::vector<std::vector<std::string>> objects_rows;

  // "sim paper" / "kitti-replay 0000", from metrics.json's run record.
  std::string title() const;
};

RunResults ReadRunResults(const std::string& dir);

// Comma-separated file with a header line; every row must have the header's number of fields.
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> line_numbers;
  int column(const std::string& name, const std::string& path) const;  // throws if absent
};
CsvTable ReadCsv(const std::string& path);
// The same, and its header must begin with `columns` (in that order); otherwise an error naming the file,
// the columns expected and those found.
CsvTable ReadCsv(const std::string& path, const std::vector<std::string>& columns);

}  // namespace dslam
