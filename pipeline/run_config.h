#pragma once
// Everything a run is configured by; loaded from YAML at the edge (pipeline/config_yaml.h).

#include "backend/backend_params.h"
#include "data/image_dataset.h"
#include "frontend/dynamic_object_classifier.h"
#include "frontend/frontend_params.h"
#include "pipeline/mask_source.h"

namespace dslam {

struct RunConfig {
  BackendParams backend;
  ClassifierParams classifier;
  FrontendParams frontend;      // image runs only
  ImageDatasetOptions dataset;  // image runs only
  MaskSourceParams masks;       // image runs only
  void validate() const {
    backend.validate();
    classifier.validate();
    frontend.validate();
    dataset.validate();
    masks.validate();
    // Masks made per frame number their objects anew each frame: only the front-end's association
    // (flow-propagated overlap) can keep an object's id.
    if (masks.source == MaskSourceKind::kLidarClusters && frontend.association.mask_ids_tracked)
      throw std::invalid_argument(
          "masks.source lidar_clusters numbers objects per frame: set frontend.mask_ids_tracked to false");
  }
};

// The mask source's settings with what it takes from the dataset's (the LiDAR depth's fill radius).
inline MaskSourceParams MaskSourceOf(const RunConfig& config) {
  MaskSourceParams masks = config.masks;
  masks.depth_fill_radius_px = config.dataset.lidar_fill_radius_px;
  return masks;
}

}  // namespace dslam
