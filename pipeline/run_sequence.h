#pragma once
// Runs the front-end labelling and the three methods on a sequence and evaluates them.

#include <map>
#include <ostream>
#include <vector>

#include "data/sequence.h"
#include "output/run_report.h"
#include "pipeline/run_config.h"

namespace dslam {

struct RunSequenceOptions {
  std::vector<Method> methods = {Method::kOurs, Method::kStaticOnly, Method::kSlamMot};
  std::ostream* progress = nullptr;  // progress lines on long runs; nullptr = quiet
  std::string object_category;       // object metrics over this category only (empty: all)
  bool evaluate = true;              // false without ground truth: metrics stay empty
  // Results already computed (ours by the staged image pipeline while the front-end ran): used, and
  // evaluated, instead of running the method again.
  std::map<Method, MethodResult> precomputed;
};

MethodOutcomes RunSequence(const Sequence& seq, const RunConfig& config, const RunSequenceOptions& options = {});

}  // namespace dslam
