// The entry point of libdslam_pcl.so (lidar/pcl_module.h).
#include "lidar/pcl_module.h"

extern "C" __attribute__((visibility("default"))) const dslam::PclFunctions* dslam_pcl_functions() {
  static const dslam::PclFunctions functions{{dslam::PclFunctions::kVersion, sizeof(dslam::PclFunctions)},
                                             &dslam::SegmentLidarObjectsWithPcl,
                                             &dslam::RegisterPointsWithPcl};
  return &functions;
}
