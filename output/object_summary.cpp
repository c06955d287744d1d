#include "output/object_summary.h"

#include "output/whole_file.h"

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

#include "output/text_format.h"

namespace dslam {
namespace {
std::string Num(const std::optional<double>& v, int precision) { return FormatFixed(v, precision, ""); }
}  // namespace

void WriteObjectsCsv(const std::string& path, const std::vector<ObjectSummary>& objects) {
  WholeFile out(path);
  out << "object_id,category,gt_frame_pairs,frames_estimated,omte_pct,omre_deg_per_m,omse_pct,"
         "mean_gt_speed_kmh,mean_est_speed_kmh\n";
  for (const auto& o : objects)
    out << o.object_id << ',' << o.category << ',' << o.gt_pairs << ',' << o.frames_estimated << ','
        << Num(o.metrics.omte_pct, 6) << ',' << Num(o.metrics.omre_deg_per_m, 6) << ',' << Num(o.metrics.omse_pct, 6)
        << ',' << Num(o.mean_gt_speed_kmh, 4) << ',' << Num(o.mean_est_speed_kmh, 4) << '\n';
  out.commit();
}

std::string FormatObjectTable(const std::vector<ObjectSummary>& objects, const std::string& title) {
  std::ostringstream out;
  out << title << '\n';
  char buf[200];
  std::snprintf(buf, sizeof buf, "%6s %-11s %7s %9s %11s %9s %14s\n", "object", "category", "frames", "OMTE(%)",
                "OMRE(deg/m)", "OMSE(%)", "speed gt/est");
  out << buf;
  for (const auto& o : objects) {
    const std::string speeds = o.mean_gt_speed_kmh ? Num(o.mean_gt_speed_kmh, 1) + "/" + Num(o.mean_est_speed_kmh, 1) + " km/h"
                                                   : "-";
    auto cell = [](const std::optional<double>& v, int p) { return FormatFixed(v, p, "-"); };
    std::snprintf(buf, sizeof buf, "%6d %-11s %3d/%-3d %9s %11s %9s %14s\n", o.object_id, o.category.c_str(),
                  o.frames_estimated, o.gt_pairs, cell(o.metrics.omte_pct, 2).c_str(),
                  cell(o.metrics.omre_deg_per_m, 3).c_str(), cell(o.metrics.omse_pct, 2).c_str(), speeds.c_str());
    out << buf;
  }
  return out.str();
}

}  // namespace dslam
