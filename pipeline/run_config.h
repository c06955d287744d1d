#pragma once
// Everything a run is configured by; loaded from YAML at the edge (pipeline/config_yaml.h).

#include "backend/backend_params.h"
#include "frontend/dynamic_object_classifier.h"

namespace dslam {

struct RunConfig {
  BackendParams backend;
  ClassifierParams classifier;
  void validate() const {
    backend.validate();
    classifier.validate();
  }
};

}  // namespace dslam
