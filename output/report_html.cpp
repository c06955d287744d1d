#include "output/report_html.h"

#include <fstream>
#include <stdexcept>

#include "output/text_format.h"

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

std::string JsonCell(const nlohmann::json& v) {
  if (v.is_number()) return FormatFixed(v.get<double>(), 4, "-");
  if (v.is_null()) return "-";
  return Escape(v.dump());
}
}  // namespace

void WriteReportHtml(const RunResults& r, const std::vector<std::string>& figure_files, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  const std::string title = Escape(r.title());
  out << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>dslam: " << title << "</title>\n"
      << "<style>body{font-family:sans-serif;margin:2em;max-width:1700px}table{border-collapse:collapse;margin:1em 0}"
         "td,th{border:1px solid #bbb;padding:4px 10px;text-align:right}th{background:#eee}"
         "img{max-width:100%;border:1px solid #ddd;margin:0.5em 0}</style></head><body>\n"
      << "<h1>dslam: " << title << "</h1>\n";

  // Metrics: rows = metrics, columns = methods (static-only, SLAM+MOT, ours).
  const auto& methods = r.metrics.contains("methods") ? r.metrics["methods"] : nlohmann::json::object();
  const std::vector<std::pair<std::string, std::string>> columns = {
      {"static_only", "static-only"}, {"slam_mot", "SLAM+MOT"}, {"ours", "ours"}};
  std::vector<std::string> keys;
  if (methods.contains("ours"))
    for (const auto& [key, value] : methods["ours"].items()) keys.push_back(key);
  out << "<h2>Metrics</h2>\n<table><tr><th>metric</th>";
  for (const auto& [id, label] : columns) out << "<th>" << label << "</th>";
  out << "</tr>\n";
  for (const auto& key : keys) {
    out << "<tr><th>" << Escape(key) << "</th>";
    for (const auto& [id, label] : columns)
      out << "<td>" << (methods.contains(id) && methods[id].contains(key) ? JsonCell(methods[id][key]) : "-") << "</td>";
    out << "</tr>\n";
  }
  out << "</table>\n";

  out << "<h2>Objects (ours)</h2>\n";
  if (r.objects_header.empty()) {
    out << "<p>No objects.csv in this result directory.</p>\n";
  } else {
    out << "<table><tr>";
    for (const auto& h : r.objects_header) out << "<th>" << Escape(h) << "</th>";
    out << "</tr>\n";
    for (const auto& row : r.objects_rows) {
      out << "<tr>";
      for (const auto& cell : row) out << "<td>" << Escape(cell) << "</td>";
      out << "</tr>\n";
    }
    out << "</table>\n";
  }
  out << "<h2>Figures</h2>\n";
  for (const auto& f : figure_files) out << "<p><img src=\"" << Escape(f) << "\" alt=\"" << Escape(f) << "\"></p>\n";
  out << "<p>Run record: <code>" << Escape(r.metrics.value("run", nlohmann::json::object()).dump()) << "</code></p>\n";
  out << "</body></html>\n";
  if (!out) throw std::runtime_error("error while writing " + path);
}

}  // namespace dslam
