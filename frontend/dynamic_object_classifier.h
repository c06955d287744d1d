#pragma once
// Static/dynamic decision per object and frame transition by camera-compensated scene flow:
// the object's points at k are brought into camera k-1 with the relative camera motion (from the
// static points by 3D-3D RANSAC when there are enough, else the odometry), then the object's own
// rigid motion is fitted; its speed at the centroid decides.

#include "data/measurements.h"
#include "geometry/rigid_alignment.h"

namespace dslam {

struct ClassifierParams {
  double dynamic_speed_threshold_mps = 0.5;
  int min_static_inliers = 10;  // below: fall back to odometry for the camera motion
  RansacParams static_ransac{100, 0.2, 3, 11};
  RansacParams object_ransac{100, 0.3, 4, 13};

  void validate() const;
};

class DynamicObjectClassifier {
 public:
  DynamicObjectClassifier(const ClassifierParams& params, double frame_rate_hz);

  // Relative camera motion T_prev_curr between the two frames (static points, else odometry, else identity).
  SE3 cameraMotion(const FrameMeasurement& prev, const FrameMeasurement& curr) const;
  // Speed (m/s) of an object between the frames in the world, or a negative value when the object
  // is absent from either frame or has too few consistent tracks.
  double objectSpeedMps(const ObjectObservation& prev, const ObjectObservation& curr, const SE3& T_prev_curr) const;
  // Sets is_dynamic of every object of `curr`; objects not seen in `prev` stay dynamic.
  void label(const FrameMeasurement& prev, FrameMeasurement* curr) const;

 private:
  ClassifierParams params_;
  double frame_rate_hz_;
};

}  // namespace dslam

namespace dslam {
// Labels every frame of a sequence against its predecessor (the first frame keeps its defaults).
void LabelDynamicObjects(const ClassifierParams& params, double frame_rate_hz, std::vector<FrameMeasurement>* frames);
}  // namespace dslam
