#pragma once
// A self-contained report page (no server, no internet): the metrics of every method, the
// per-object table and the figures, which it references by relative file name.

#include <string>
#include <vector>

#include "output/result_reader.h"

namespace dslam {

void WriteReportHtml(const RunResults& results, const std::vector<std::string>& figure_files, const std::string& path);

}  // namespace dslam
