#pragma once
// YAML <-> RunConfig. Unknown keys are errors (a typo must not silently fall back to a default);
// missing keys keep their defaults. Errors throw std::invalid_argument naming the file and key.

#include <string>

#include "pipeline/run_config.h"

namespace dslam {

RunConfig LoadRunConfig(const std::string& path);
RunConfig ParseRunConfig(const std::string& yaml_text, const std::string& source_name = "<string>");
std::string RunConfigToYaml(const RunConfig& config);

}  // namespace dslam
