#pragma once
// Static/dynamic decisions per object and frame transition by camera-compensated scene flow: the
// object's points at k are brought into camera k-1 with the relative camera motion (from the static
// points by 3D-3D RANSAC when there are enough, else the odometry), then the object's own rigid motion
// is fitted. Two decisions come out of it:
//  - for the estimator (is_dynamic): the object's points may serve as static structure only if its
//    centroid moved slower than the estimator's speed threshold AND its displacement is not statistically
//    significant given the point noise and the camera motion's uncertainty (a chi-square test), over
//    consecutive transitions: an object that jitters by a few centimetres (e.g. a replayed KITTI label)
//    must not be merged into the static map, where it pulls the camera;
//  - for the report (reported): over the object's transitions of the last `motion_window_s`, it is
//    moving when both their net displacement and their typical (per-axis median) one are faster than
//    the report's speed threshold and significant, or the typical one is clearly fast (three times
//    that threshold); standing otherwise. A parked car's jitter cancels in the net displacement, one wrong
//    fit (a re-acquired track) does not move the median; such a car keeps its own motion in the estimator
//    but is reported standing, with speed 0. Until the window holds half its length (a car entering
//    the view or back from an occlusion) the object is unsupported, its motion not reported at all,
//    unless one transition alone is clearly moving, fitted on enough tracks (an oncoming car seen for a
//    few frames) and, for a small mask, clearly moving even at the low end of its uncertainty.

#include <deque>
#include <map>
#include <optional>

#include "data/measurements.h"
#include "geometry/rigid_alignment.h"

namespace dslam {

struct ClassifierParams {
  // The estimator's test: slower than this and not significant, an object may join the static map.
  double dynamic_speed_threshold_mps = 0.5;
  // The report's: an object is reported moving only this fast (the metrics' moving pair, docs/design.md §9: 1 m/s). Higher than
  // the estimator's, since a slow, significant motion keeps an object out of the static map, but a vehicle
  // acting on the report needs it to mean what the evaluation means by moving.
  double report_speed_threshold_mps = 1.0;
  double static_test_chi2 = 16.27;  // chi-square (3 dof) bound of a static object's displacement: 99.9 %
  // Consecutive still transitions before an object is called static: one lucky frame of a
  // slightly moving object must not merge it into the static map.
  int min_static_transitions = 2;
  // Fewer static tracks: the camera motion comes from odometry. Fewer object tracks: one transition alone
  // does not report a new object moving (see kClearMotionFactor).
  int min_static_inliers = 10;
  // An object whose mask covers less than this share of the image, % (the paper's 2 % on KITTI: a far car,
  // or one mostly hidden or out of view) is reported moving on one transition alone only when even the
  // low end of its speed's bound (static_test_chi2) is clearly fast. Objects without a mask: no such rule.
  double small_object_area_pct = 2.0;
  double motion_window_s = 0.5;  // the displacement tested is the sum over the transitions this long
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
  Vec3 displacement_camera_prev = Vec3::Zero();  // of the centroid over the transition, camera k-1 axes
  double variance_m2 = 0.0;                      // per axis, of that displacement if the object were static
  int inliers = 0;                               // tracks the motion was fitted on
};

class DynamicObjectClassifier {
 public:
  DynamicObjectClassifier(const ClassifierParams& params, double frame_rate_hz);

  // Relative camera motion T_prev_curr between the two frames (static points, else odometry, else identity).
  CameraMotionEstimate cameraMotion(const FrameMeasurement& prev, const FrameMeasurement& curr) const;
  // The object's own motion between the frames, `periods` frame periods apart (transitionPeriods); nullopt
  // with too few consistent tracks.
  std::optional<ObjectMotionTest> testObjectMotion(const ObjectObservation& prev, const ObjectObservation& curr,
                                                   const CameraMotionEstimate& camera, double periods = 1.0) const;
  // How many frame periods the transition spans: its stamps' step in periods when that is a gap (kGapPeriods,
  // data/measurements.h), else 1 (speeds stay per period).
  double transitionPeriods(const FrameMeasurement& prev, const FrameMeasurement& curr) const;
  // Sets is_dynamic and reported of every object of `curr`; objects not seen in `prev` stay dynamic and
  // unsupported. Call once per frame in order: it counts each object's consecutive still transitions
  // and keeps its last transitions.
  void label(const FrameMeasurement& prev, FrameMeasurement* curr);

 private:
  // The object's last transitions (at most the window), displacements in the axes of the first camera, per
  // frame period (a transition over a gap counts its displacement per period, its variance alike).
  struct Window {
    std::deque<Vec3> displacement;
    std::deque<double> variance_m2;
    // The last transition alone: fast (for a small mask, even at the low end of its bound), significant,
    // on enough tracks.
    bool last_clearly_moving = false;
  };
  // What the object's window supports: moving when its net and its typical (median) displacement are
  // both fast and significant, or the typical one is clearly fast; unsupported while it holds less than
  // half its length (unless the last transition is clearly moving); standing otherwise.
  ReportedMotion reportOverWindow(const Window& window) const;

  ClassifierParams params_;
  double frame_rate_hz_;
  int window_transitions_ = 1;
  Mat3 R_first_camera_ = Mat3::Identity();  // camera k-1's rotation from the first camera's axes
  std::map<int, int> static_streak_;  // object id -> consecutive still transitions up to the last frame
  std::map<int, Window> windows_;     // object id -> its last transitions (objects seen in the last frame)
};

}  // namespace dslam

namespace dslam {
// Labels every frame of a sequence against its predecessor (the first frame keeps its defaults).
void LabelDynamicObjects(const ClassifierParams& params, double frame_rate_hz, std::vector<FrameMeasurement>* frames);
}  // namespace dslam
