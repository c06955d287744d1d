#include "output/report_html.h"

#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "output/text_format.h"
#include "output/whole_file.h"

namespace dslam {
namespace {

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// A metric of metrics.json as a person reads it.
struct MetricRow {
  const char* key;
  const char* name;
  const char* unit;  // "" for a count
  double scale;      // value shown = value * scale (a fraction as %)
  int decimals;      // 0: an integer
};

// The paper's order (Table I and II): relative errors first, then the absolute ones and the counts.
const std::vector<MetricRow> kCameraRows = {
    {"rte_pct", "Relative translation error (RTE)", "%", 1.0, 2},
    {"rre_deg_per_m", "Relative rotation error (RRE)", "°/m", 1.0, 4},
    {"ate_m", "Absolute trajectory error (ATE)", "m", 1.0, 3},
    {"mean_step_te_m", "Mean step translation error (path under 1 m)", "m", 1.0, 4},
    {"mean_step_re_deg", "Mean step rotation error (path under 1 m)", "°", 1.0, 4},
    {"rse_pct", "Relative structure error (RSE)", "%", 1.0, 2},
    {"camera_path_m", "Camera path length", "m", 1.0, 1},
};
const std::vector<MetricRow> kObjectRows = {
    {"omte_pct", "Object motion translation error (OMTE)", "%", 1.0, 2},
    {"omre_deg_per_m", "Object motion rotation error (OMRE)", "°/m", 1.0, 4},
    {"omse_pct", "Object speed error (OMSE)", "%", 1.0, 2},
    {"me_t_m", "Mean motion error, translation", "m", 1.0, 3},
    {"me_r_deg", "Mean motion error, rotation", "°", 1.0, 3},
    {"speed_err_kmh", "Mean speed error", "km/h", 1.0, 2},
    {"object_coverage", "Moving object frame pairs estimated (coverage)", "%", 100.0, 1},
    {"object_coverage_measurable", "Measurable moving pairs estimated (coverage)", "%", 100.0, 1},
    {"object_gt_pairs", "Ground-truth object frame pairs", "", 1.0, 0},
    {"object_gt_moving_pairs", "Ground-truth moving object frame pairs", "", 1.0, 0},
    {"object_moving_pairs_estimated", "Moving object frame pairs estimated", "", 1.0, 0},
    {"static_pairs_false_dynamic_frac", "Standing object pairs reported moving", "%", 100.0, 1},
    {"static_pairs_mean_speed_mps", "Mean speed reported for standing objects", "m/s", 1.0, 3},
};
const std::vector<MetricRow> kRunRows = {{"wall_time_s", "Back-end wall time", "s", 1.0, 2}};
// Shown elsewhere in another unit: not repeated among the other figures.
const std::set<std::string> kShownAs = {"speed_err_mps"};

std::string Number(double v, int decimals) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(decimals);
  out << v;
  return out.str();
}

std::string Cell(const nlohmann::json& methods, const std::string& method, const MetricRow& row) {
  if (!methods.contains(method) || !methods[method].contains(row.key)) return "-";
  const nlohmann::json& v = methods[method][row.key];
  if (!v.is_number()) return "-";
  return Number(v.get<double>() * row.scale, row.decimals);
}

void MetricTable(std::ostream& out, const std::string& caption, const nlohmann::json& methods,
                 const std::vector<std::pair<std::string, std::string>>& columns, const std::vector<MetricRow>& rows) {
  std::vector<std::pair<std::string, std::string>> present;
  for (const auto& c : columns)
    if (methods.contains(c.first)) present.push_back(c);
  if (present.empty()) return;
  out << "<table><caption>" << Escape(caption) << "</caption><tr><th>metric</th><th>unit</th>";
  for (const auto& [id, label] : present) out << "<th>" << Escape(label) << "</th>";
  out << "</tr>\n";
  for (const MetricRow& row : rows) {
    bool any = false;
    for (const auto& [id, label] : present) any = any || Cell(methods, id, row) != "-";
    if (!any) continue;  // e.g. the short-path step errors of a long run
    out << "<tr><th>" << Escape(row.name) << "</th><td class=\"unit\">" << Escape(row.unit) << "</td>";
    for (const auto& [id, label] : present) out << "<td>" << Cell(methods, id, row) << "</td>";
    out << "</tr>\n";
  }
  out << "</table>\n";
}

const char* kStyle =
    "<style>body{font-family:sans-serif;margin:2em;max-width:1700px}table{border-collapse:collapse;margin:1em 0}"
    "caption{text-align:left;font-weight:bold;padding:4px 0}td,th{border:1px solid #bbb;padding:4px 10px;"
    "text-align:right}th{background:#eee}td.unit,th:first-child{text-align:left}"
    "table.sortable th{cursor:pointer}figure{margin:1em 0}figcaption{color:#333;margin:0.3em 0}"
    "img{max-width:100%;border:1px solid #ddd}</style>\n";

// Click a column's header to sort the table by it (numbers as numbers), again to reverse.
const char* kSortScript =
    "<script>document.querySelectorAll('table.sortable').forEach(function(t){"
    "t.querySelectorAll('th').forEach(function(h,i){h.addEventListener('click',function(){"
    "var rows=Array.from(t.querySelectorAll('tr')).slice(1);var up=h.dataset.dir!=='up';h.dataset.dir=up?'up':'down';"
    "rows.sort(function(a,b){var x=a.children[i].textContent,y=b.children[i].textContent;"
    "var p=parseFloat(x),q=parseFloat(y);var c=(isNaN(p)||isNaN(q))?x.localeCompare(y):p-q;return up?c:-c;});"
    "rows.forEach(function(r){t.appendChild(r);});});});});</script>\n";

// The columns of our CSV files as a person reads them: a name with its unit, and the decimals shown (-1: as
// written, text or an integer).
struct Column {
  const char* name;
  int decimals;
};
const std::map<std::string, Column> kColumns = {
    {"object_id", {"Object", -1}},
    {"category", {"Category", -1}},
    {"gt_frame_pairs", {"Ground-truth frame pairs", 0}},
    {"frames_estimated", {"Frames estimated", 0}},
    {"omte_pct", {"OMTE (%)", 2}},
    {"omre_deg_per_m", {"OMRE (°/m)", 4}},
    {"omse_pct", {"OMSE (%)", 2}},
    {"mean_gt_speed_kmh", {"Mean true speed (km/h)", 1}},
    {"mean_est_speed_kmh", {"Mean estimated speed (km/h)", 1}},
    {"component", {"Component", -1}},
    {"setting", {"Setting", -1}},
    {"method", {"Method", -1}},
    {"rte_pct", {"RTE (%)", 2}},
    {"rre_deg_per_m", {"RRE (°/m)", 4}},
    {"ate_m", {"ATE (m)", 3}},
    {"object_coverage", {"Coverage (share of pairs)", 3}},
    {"object_pairs_estimated", {"Pairs estimated", 0}},
    {"object_gt_pairs", {"Ground-truth pairs", 0}},
    {"mask_miou", {"Mask mIoU", 3}},
    {"mask_detection_rate", {"Detection rate", 3}},
    {"tracker", {"Tracker", -1}},
    {"frame_pairs", {"Frame pairs", 0}},
    {"matches", {"Matches", 0}},
    {"object_matches", {"Matches on objects", 0}},
    {"good_matches", {"Good matches (EPE < 3 px)", 0}},
    {"mean_epe_px", {"Mean EPE (px)", 2}},
    {"mean_good_epe_px", {"Mean EPE of good matches (px)", 2}},
};

void HtmlTable(std::ostream& out, const std::string& caption, const std::vector<std::vector<std::string>>& csv,
              bool sortable) {
  if (csv.empty()) return;
  out << "<table" << (sortable ? " class=\"sortable\"" : "") << "><caption>" << Escape(caption) << "</caption><tr>";
  std::vector<int> decimals;
  for (const auto& h : csv[0]) {
    const auto c = kColumns.find(h);
    out << "<th>" << Escape(c == kColumns.end() ? h : c->second.name) << "</th>";
    decimals.push_back(c == kColumns.end() ? -1 : c->second.decimals);
  }
  out << "</tr>\n";
  for (size_t i = 1; i < csv.size(); ++i) {
    out << "<tr>";
    for (size_t j = 0; j < csv[i].size(); ++j) {
      const std::string& cell = csv[i][j];
      std::string shown = cell.empty() ? "-" : cell;
      if (j < csv[0].size() && csv[0][j] == "method") {
        static const std::map<std::string, std::string> kMethods = {{"static_only", "static-only"}, {"slam_mot", "SLAM+MOT"}};
        const auto m = kMethods.find(cell);
        if (m != kMethods.end()) shown = m->second;
      } else if (!cell.empty() && j < decimals.size() && decimals[j] >= 0) {
        char* end = nullptr;
        const double v = std::strtod(cell.c_str(), &end);
        if (end && *end == '\0') shown = Number(v, decimals[j]);
      }
      out << "<td>" << Escape(shown) << "</td>";
    }
    out << "</tr>\n";
  }
  out << "</table>\n";
}

std::string Caption(const std::string& file) {
  static const std::map<std::string, std::string> captions = {
      {"trajectory.png",
       "Top view: the camera's true path (black) and its estimate (red), and each moving object's true centroid "
       "track (dashed) against the track its estimated motions give (solid)."},
      {"speeds.png", "Each moving object's estimated speed (solid) against the true speed (dashed), frame by frame."},
      {"errors.png", "Per frame: the camera's relative translation and rotation errors and the mean object motion error."},
      {"map.png", "The estimated map in 3D: static points and standing cars grey, moving objects' points in colour, "
                  "the camera path red."},
      {"study_effects.png",
       "The camera (RTE, RRE) and object (OMTE, OMRE, OMSE) errors with each front-end component made realistic in "
       "turn, the others exact: which component costs most."},
      {"study_tracking.png",
       "Flow against matching: correspondences found from one frame to the next (all, on objects, under 3 px of "
       "the exact one) and their end-point error."}};
  const auto it = captions.find(file);
  if (it != captions.end()) return it->second;
  if (file.rfind("frame_", 0) == 0)
    return "Frame " + file.substr(6, file.size() - 10) + " as the run saw it: each instance mask tinted, each object "
           "estimated there boxed with its id and speed (green: reported moving; grey: standing).";
  return file;
}

void Figures(std::ostream& out, const std::vector<std::string>& files) {
  if (files.empty()) return;
  out << "<h2>Figures</h2>\n";
  for (const auto& f : files)
    out << "<figure><figcaption><a href=\"" << Escape(f) << "\">" << Escape(f) << "</a>: " << Escape(Caption(f))
        << "</figcaption><img src=\"" << Escape(f) << "\" alt=\"" << Escape(Caption(f)) << "\"></figure>\n";
}

}  // namespace

void WriteReportHtml(const RunResults& r, const std::vector<std::string>& figure_files, const std::string& path) {
  std::ostringstream out;
  const std::string title = Escape(r.title());
  out << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>dslam: " << title << "</title>\n"
      << kStyle << "</head><body>\n<h1>dslam: " << title << "</h1>\n";

  const nlohmann::json methods = r.metrics.contains("methods") ? r.metrics["methods"] : nlohmann::json::object();
  out << "<h2>Metrics</h2>\n";
  MetricTable(out, "Camera", methods, {{"static_only", "static-only"}, {"slam_mot", "SLAM+MOT"}, {"ours", "ours"}},
              kCameraRows);
  MetricTable(out, "Objects", methods, {{"slam_mot", "SLAM+MOT"}, {"ours", "ours"}}, kObjectRows);
  MetricTable(out, "Run", methods, {{"static_only", "static-only"}, {"slam_mot", "SLAM+MOT"}, {"ours", "ours"}},
              kRunRows);
  // Figures this page does not know yet: shown by their keys rather than dropped.
  std::set<std::string> known(kShownAs);
  for (const auto* rows : {&kCameraRows, &kObjectRows, &kRunRows})
    for (const MetricRow& row : *rows) known.insert(row.key);
  std::set<std::string> other_keys;
  for (const auto& [method, values] : methods.items())
    for (const auto& [key, value] : values.items())
      if (!known.count(key)) other_keys.insert(key);
  if (!other_keys.empty()) {
    std::vector<MetricRow> rows;
    for (const std::string& k : other_keys) rows.push_back({k.c_str(), k.c_str(), "", 1.0, 4});
    MetricTable(out, "Other figures", methods, {{"static_only", "static-only"}, {"slam_mot", "SLAM+MOT"}, {"ours", "ours"}},
                rows);
  }

  out << "<h2>Objects (ours)</h2>\n";
  if (r.objects_header.empty()) {
    out << "<p>No objects.csv in this result directory.</p>\n";
  } else {
    std::vector<std::vector<std::string>> csv = {r.objects_header};
    csv.insert(csv.end(), r.objects_rows.begin(), r.objects_rows.end());
    HtmlTable(out, "Per object: click a column to sort by it", csv, true);
  }
  Figures(out, figure_files);
  out << "<p>Run record: <code>" << Escape(r.metrics.value("run", nlohmann::json::object()).dump()) << "</code></p>\n";
  out << kSortScript << "</body></html>\n";
  WholeFile file(path);
  file << out.str();
  file.commit();
}

void WriteStudyReportHtml(const std::string& title, const std::vector<std::vector<std::string>>& study_csv,
                          const std::vector<std::vector<std::string>>& tracking_csv,
                          const std::vector<std::string>& figure_files, const std::string& path) {
  std::ostringstream out;
  out << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>dslam study: " << Escape(title) << "</title>\n"
      << kStyle << "</head><body>\n<h1>dslam study: " << Escape(title) << "</h1>\n"
      << "<p>One front-end component made realistic at a time, the others exact (docs/study.md). "
         "Files: <a href=\"study.csv\">study.csv</a>, <a href=\"tracking.csv\">tracking.csv</a>.</p>\n";
  HtmlTable(out, "Errors per setting and method (RTE and OMTE/OMSE in %, RRE and OMRE in °/m, ATE in m)", study_csv, true);
  HtmlTable(out, "Correspondences per frame pair and their end-point error (px) against the exact ones", tracking_csv, true);
  Figures(out, figure_files);
  out << kSortScript << "</body></html>\n";
  WholeFile file(path);
  file << out.str();
  file.commit();
}

}  // namespace dslam
