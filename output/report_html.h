#pragma once
// Self-contained report pages (no server, no internet): what a person reads after a run or a study.
// Metrics in the paper's order with their names and units, one table per method family as in the paper's
// tables (camera: static-only, SLAM+MOT and ours; objects: SLAM+MOT and ours), the per-object table
// sortable by any column, and each figure with a line saying what it shows. Written whole (no half page).

#include <string>
#include <vector>

#include "output/result_reader.h"

namespace dslam {

// `figure_files`: file names next to the page (trajectory.png, speeds.png, errors.png, map.png).
void WriteReportHtml(const RunResults& results, const std::vector<std::string>& figure_files, const std::string& path);

// The study's page (dslam study): its two CSVs (header row first) as tables, and its figures.
void WriteStudyReportHtml(const std::string& title, const std::vector<std::vector<std::string>>& study_csv,
                          const std::vector<std::vector<std::string>>& tracking_csv,
                          const std::vector<std::string>& figure_files, const std::string& path);

}  // namespace dslam
