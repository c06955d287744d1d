#pragma once
// YAML <-> RunConfig. Unknown keys are errors (a typo must not silently fall back to a default);
// missing keys keep their defaults. Errors throw std::invalid_argument naming the file and key.

#include <string>

#include "pipeline/run_config.h"

namespace dslam {

// The keys a file sets are applied over `base` (the built-in defaults, or a command's defaults); what the
// file does not set keeps the base's value. A section or key given twice is an error.
RunConfig LoadRunConfig(const std::string& path, const RunConfig& base = RunConfig{});
RunConfig ParseRunConfig(const std::string& yaml_text, const std::string& source_name = "<string>",
                         const RunConfig& base = RunConfig{});
std::string RunConfigToYaml(const RunConfig& config);

}  // namespace dslam
