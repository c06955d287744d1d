#pragma once
// Everything a run is configured by; loaded from YAML at the edge (pipeline/config_yaml.h).

#include "backend/backend_params.h"
#include "data/image_dataset.h"
#include "frontend/dynamic_object_classifier.h"
#include "frontend/frontend_params.h"

namespace dslam {

struct RunConfig {
  BackendParams backend;
  ClassifierParams classifier;
  FrontendParams frontend;      // image runs only
  ImageDatasetOptions dataset;  // image runs only
  void validate() const {
    backend.validate();
    classifier.validate();
    frontend.validate();
    dataset.validate();
  }
};

}  // namespace dslam
