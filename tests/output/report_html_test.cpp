// report.html is read by a person: metric names with units in the paper's order, one table per method
// family, integers without decimals, a sortable per-object table with named columns, captioned figures;
// nothing of metrics.json dropped.
#include "output/report_html.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "support/temp_paths.h"

namespace dslam {
namespace {

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ReportHtml, NamesMetricsWithUnitsInThePapersOrderInOneTablePerMethodFamily) {
  RunResults r;
  r.metrics["methods"]["ours"] = {{"rte_pct", 1.23456}, {"rre_deg_per_m", 0.01234}, {"ate_m", 0.5},
                                  {"omte_pct", 2.5},     {"omse_pct", 1.5},          {"object_gt_pairs", 35},
                                  {"object_coverage", 0.75}, {"wall_time_s", 2.0},   {"new_metric", 7.0}};
  r.metrics["methods"]["static_only"] = {{"rte_pct", 1.5}, {"rre_deg_per_m", 0.02}, {"ate_m", 0.6}};
  r.metrics["methods"]["slam_mot"] = {{"rte_pct", 1.5}, {"omte_pct", 3.0}, {"omse_pct", 2.0}, {"object_gt_pairs", 35}};
  r.metrics["run"] = {{"command", "run"}};
  r.objects_header = {"object_id", "category", "gt_frame_pairs", "frames_estimated", "omte_pct"};
  r.objects_rows = {{"7", "VEHICLE", "12", "11", "1.234567"}, {"9", "VEHICLE", "3", "0", ""}};
  const std::string path = test::TempPath("report.html");
  WriteReportHtml(r, {"trajectory.png", "speeds.png"}, path);
  const std::string html = ReadAll(path);

  // Human names and units, not JSON keys; the paper's order (RTE before RRE before ATE; OMTE before OMSE).
  for (const char* name : {"Relative translation error (RTE)", "Relative rotation error (RRE)",
                           "Object motion translation error (OMTE)", "Object speed error (OMSE)"})
    EXPECT_NE(html.find(name), std::string::npos) << name;
  EXPECT_EQ(html.find("<th>rte_pct</th>"), std::string::npos);
  EXPECT_LT(html.find("(RTE)"), html.find("(RRE)"));
  EXPECT_LT(html.find("(RRE)"), html.find("(ATE)"));
  EXPECT_LT(html.find("(OMTE)"), html.find("(OMSE)"));
  // One table per family: the camera's with static-only, the objects' without it.
  const size_t camera = html.find("<caption>Camera</caption>"), objects = html.find("<caption>Objects</caption>");
  ASSERT_NE(camera, std::string::npos);
  ASSERT_NE(objects, std::string::npos);
  const std::string objects_table = html.substr(objects, html.find("</table>", objects) - objects);
  EXPECT_EQ(objects_table.find("static-only"), std::string::npos);
  EXPECT_NE(objects_table.find("SLAM+MOT"), std::string::npos);
  // Counts without decimals, fractions as percentages, values rounded for reading.
  EXPECT_NE(objects_table.find("<td>35</td>"), std::string::npos);
  EXPECT_EQ(html.find("35.0"), std::string::npos);
  EXPECT_NE(objects_table.find("<td>75.0</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>1.23</td>"), std::string::npos);
  // A figure this page does not know is still shown, under its key.
  EXPECT_NE(html.find("Other figures"), std::string::npos);
  EXPECT_NE(html.find("new_metric"), std::string::npos);
  // The per-object table: named columns, sortable, integers kept, numbers rounded.
  EXPECT_NE(html.find("class=\"sortable\""), std::string::npos);
  EXPECT_NE(html.find("<th>Frames estimated</th>"), std::string::npos);
  EXPECT_NE(html.find("<td>1.23</td><"), std::string::npos);
  EXPECT_NE(html.find("addEventListener('click'"), std::string::npos);
  // Each figure with a caption saying what it shows.
  EXPECT_NE(html.find("<figcaption><a href=\"speeds.png\">speeds.png</a>: Each moving object's estimated speed"),
            std::string::npos);
}

TEST(ReportHtml, TheStudysPageShowsBothTablesWithNamedColumnsAndLinksItsFigures) {
  const std::string path = test::TempPath("study_report.html");
  WriteStudyReportHtml("scene", {{"component", "setting", "method", "rte_pct"}, {"exact", "exact", "slam_mot", "1.23456"}},
                       {{"tracker", "matches", "mean_epe_px"}, {"lk", "805.09", "0.99287"}},
                       {"study_effects.png", "study_tracking.png"}, path);
  const std::string html = ReadAll(path);
  EXPECT_NE(html.find("<th>RTE (%)</th>"), std::string::npos);
  EXPECT_NE(html.find("<td>SLAM+MOT</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>1.23</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>805</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>0.99</td>"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"study_effects.png\">"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"study_tracking.png\">"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"study.csv\">"), std::string::npos);
}

}  // namespace
}  // namespace dslam
