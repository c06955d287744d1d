#pragma once
// Static/dynamic decision per object and frame transition by camera-compensated scene flow:
// the object's points at k are brought into camera k-1 with the relative camera motion (from the
// static points by 3D-3D RANSAC when there are enough, else the odometry), then the object's own
// rigid motion is fitted. The object is static only if its centroid moved slower than the speed
// threshold AND its displacement is not statistically significant given the point noise and the
// camera motion's uncertainty (a chi-square test): an object that jitters by a few centimetres
// (e.g. a replayed KITTI label) must not be merged into the static map.

#include <map>
#include <optional>

#include "data/measurements.h"
#include "geometry/rigid_alignment.h"

namespace dslam {

struct ClassifierParams {
  double dynamic_speed_threshold_mps = 0.5;
  double static_test_chi2 = 16.27;  // chi-square (3 dof) bound of a static object's displacement: 99.9 %
  // Consecutive still transitions before an object is called static: one lucky frame of a
  // slightly moving object must not merge it into the static map.
  int min_static_transitions = 2;
  int min_static_inliers = 10;  // below: fall back to odometry for the camera motion
  RansacParams static_ransac{100, 0.2, 3, 11};
  RansacParams object_ransac{100, 0.3, 4, 13};

  void validate() const;
};

struct CameraMotionEstimate {
  SE3 T_prev_curr;
  bool from_static_points = false;
  double translation_sigma_m = 0.0;   // per axis
  double rotation_sigma_rad = 0.0;
};

struct ObjectMotionTest {
  double speed_mps = 0.0;  // of the centroid, camera motion compensated
  double chi2 = 0.0;       // squared displacement over its variance if the object were static
  bool significant = false;
};

class DynamicObjectClassifier {
 public:
  DynamicObjectClassifier(const ClassifierParams& params, double frame_rate_hz);

  // Relative camera motion T_prev_curr between the two frames (static points, else odometry, else identity).
  CameraMotionEstimate cameraMotion(const FrameMeasurement& prev, const FrameMeasurement& curr) const;
  // The object's own motion between the frames; nullopt with too few consistent tracks.
  std::optional<ObjectMotionTest> testObjectMotion(const ObjectObservation& prev, const ObjectObservation& curr,
                                                   const CameraMotionEstimate& camera) const;
  // Sets is_dynamic of every object of `curr`; objects not seen in `prev` stay dynamic. Call once per
  // frame in order: it counts each object's consecutive still transitions.
  void label(const FrameMeasurement& prev, FrameMeasurement* curr);

 private:
  ClassifierParams params_;
  double frame_rate_hz_;
  std::map<int, int> static_streak_;  // object id -> consecutive still transitions up to the last frame
};

}  // namespace dslam

namespace dslam {
// Labels every frame of a sequence against its predecessor (the first frame keeps its defaults).
void LabelDynamicObjects(const ClassifierParams& params, double frame_rate_hz, std::vector<FrameMeasurement>* frames);
}  // namespace dslam
