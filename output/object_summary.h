#pragma once
// Per-object results of a run: objects.csv and a console table like the paper's Table II.

#include <string>
#include <vector>

#include "evaluation/evaluate_run.h"

namespace dslam {

// objects.csv: id, category, frames estimated, OMTE, OMRE, OMSE, mean gt and estimated speed (km/h).
void WriteObjectsCsv(const std::string& path, const std::vector<ObjectSummary>& objects);
std::string FormatObjectTable(const std::vector<ObjectSummary>& objects, const std::string& title);

}  // namespace dslam
