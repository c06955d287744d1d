#pragma once
// Where the tests find ../shared/data (its README says what each folder holds); tests that need it skip
// with a message when it is absent.

#include <string>

namespace dslam::test {

inline std::string SharedData(const std::string& folder) { return std::string(DSLAM_SHARED_DATA_DIR) + "/" + folder; }

// KITTI tracking's ground truth and images (label_02/, oxts/, image_02/, ...).
inline std::string KittiTrackingDir() { return SharedData("kitti_tracking"); }

}  // namespace dslam::test
