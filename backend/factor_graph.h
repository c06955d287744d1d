#pragma once
// Storage of the factor graph: variables (plain double arrays Ceres optimises in place) and factors
// filed by the frame that introduced them, so a sliding window touches only its own frames.

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "backend/factors/huber_loss.h"
#include "backend/factors/pose_block.h"
#include "data/measurements.h"
#include "geometry/se3.h"

namespace dslam {



struct PointVariable {
  std::array<double, 3> p_world{};
  int64_t track_id = 0;
  int object_id = -1;  // -1: static background structure
  int first_frame = 0;
  int last_frame = 0;  // last frame whose measurement refers to it
  // Schur elimination group of the batch solver: points linked by a motion factor alternate, so that
  // the points of the first group form an independent set, as Schur solvers require.
  bool eliminate_first = true;
  // Marginalised measurements (the fixed-lag smoother folds the measurements of frames that left its
  // window into this Gaussian prior): information matrix and information vector, p ~ N(info^-1 vec, info^-1).
  Mat3 prior_info = Mat3::Zero();
  Vec3 prior_info_vec = Vec3::Zero();
  // The newest measurements of frames that left the window, kept as robust factors with their camera
  // held at its final estimate, so that their Huber weights follow the landmark's estimate (an outlier
  // is told apart only once the landmark has been seen from later frames); older ones are in the prior.
  struct HeldMeasurement {
    Mat3 A;           // whitened residual r = A (p - p_world): A = diag(1 / sigma) R_world_camera^T
    Vec3 p_world;     // the measured point, in the world through the held camera
    int frame = 0;
  };
  std::vector<HeldMeasurement> held;  // oldest first
  bool hasPrior() const { return prior_info.trace() > 0.0 || !held.empty(); }
  // The prior and the held measurements at position x: their cost (0.5 * sum of squares, Huber on the held
  // ones) and the Gauss-Newton information and gradient (IRLS weights).
  double priorCost(const Vec3& x, const HuberLoss& huber) const {
    double c = 0.0;
    if (prior_info.trace() > 0.0) {
      const Vec3 mean = prior_info.ldlt().solve(prior_info_vec);
      c += (x - mean).dot(prior_info * (x - mean));
    }
    for (const HeldMeasurement& h : held) c += huber.rho((h.A * (x - h.p_world)).squaredNorm());
    return 0.5 * c;
  }
  void priorNormalEquations(const Vec3& x, const HuberLoss& huber, Mat3* info, Vec3* gradient) const {
    *info = prior_info;
    *gradient = prior_info * x - prior_info_vec;
    for (const HeldMeasurement& h : held) {
      const Vec3 r = h.A * (x - h.p_world);
      const Mat3 AtA = huber.weight(r.squaredNorm()) * h.A.transpose() * h.A;
      *info += AtA;
      *gradient += AtA * (x - h.p_world);
    }
  }
  // Folds the oldest held measurement into the prior with its weight at position x.
  void foldOldestHeld(const Vec3& x, const HuberLoss& huber) {
    const HeldMeasurement& h = held.front();
    const Mat3 info = huber.weight((h.A * (x - h.p_world)).squaredNorm()) * h.A.transpose() * h.A;
    prior_info += info;
    prior_info_vec += info * h.p_world;
    held.erase(held.begin());
  }
  Vec3 position() const { return Vec3(p_world[0], p_world[1], p_world[2]); }
};

// An object's pose change, stored about an anchor point c near the object (not about the world
// origin): H_world = Tc * H_anchor * Tc^-1 with Tc the translation by c. The same motion, but a small
// rotation no longer swings a translation the size of the object's distance from the origin, which
// would make the problem worse conditioned the farther a run goes.
struct MotionVariable {
  PoseBlock H_anchor{};
  Vec3 anchor_world = Vec3::Zero();
  // Marginal covariance of the block's tangent [translation; rotation] (the translation is that of
  // the anchor, the rotation perturbs on the right) from the last solve; zero when unknown.
  Mat6 covariance = Mat6::Zero();
  int object_id = 0;
  int first_frame = 0;
  int last_frame = 0;

  SE3 worldMotion() const;
  static PoseBlock AnchorBlock(const SE3& H_world, const Vec3& anchor_world);
};

struct PointMeasurementEntry {
  int point_var;
  Vec3 z_camera;
  Vec3 sigma_m;
};

struct OdometryEntry {
  SE3 T_prev_curr;
  Vec6 sigma;
};

// The ternary factor l_k = H * l_{k-1}. (When the smoother marginalises l_{k-1}, it becomes a
// LinearPointFactor on l_k, H and the camera that measured l_{k-1}.)
struct PointMotionEntry {
  int prev_point_var;
  int curr_point_var;
  int motion_var;
};

// prev_motion_var = -1: the previous motion left the window; its final value is held in prev_fixed.
struct SmoothnessEntry {
  int prev_motion_var;
  int curr_motion_var;
  PoseBlock prev_fixed{};
  Vec3 prev_fixed_anchor = Vec3::Zero();
};

// What marginalising an object point at frame m leaves of its factors (backend/marginalisation.h): a
// linear (Gaussian) factor on the camera that measured it, its successor point at m+1 and the motion into
// m+1, linearised at `*_lin`: r = r0 + J [cam (-) cam_lin; point - point_lin; H (-) H_lin], tangents as
// the solver's ([dt; phi], rotation on the right). Whitened and robust-weighted already: plain squares.
struct LinearPointFactor {
  int camera_frame = -1;  // -1: the camera left the window; its columns were folded into r0
  int point_var = -1;
  int motion_var = -1;
  PoseBlock camera_lin{};
  Vec3 point_lin = Vec3::Zero();
  PoseBlock motion_lin{};  // of H_anchor
  Eigen::Matrix<double, 6, 15> J = Eigen::Matrix<double, 6, 15>::Zero();  // columns: camera, point, motion
  Vec6 r0 = Vec6::Zero();

  // The residual at these values (`camera` null once its columns were folded into r0): the one definition the
  // marginalisation and the window solver share.
  Vec6 residual(const double* camera, const Vec3& point, const double* motion) const {
    Eigen::Matrix<double, 15, 1> d = Eigen::Matrix<double, 15, 1>::Zero();
    if (camera) d.head<6>() = PoseBlockMinus(camera, camera_lin.data());
    d.segment<3>(6) = point - point_lin;
    d.tail<6>() = PoseBlockMinus(motion, motion_lin.data());
    return r0 + J * d;
  }
};

// What the cameras that left the smoother's window say about the first camera still in it: the Gaussian
// their elimination by a Schur complement left (backend/marginalisation.h), as whitened rows about the
// point it was linearised at, which it keeps while it lives (first-estimate Jacobian):
// r = r0 + R (camera (-) camera_lin). Rows beyond the information's rank are zero.
struct CameraPrior {
  int frame = -1;
  PoseBlock camera_lin{};
  Mat6 R = Mat6::Zero();
  Vec6 r0 = Vec6::Zero();

  Vec6 residual(const double* camera) const { return r0 + R * PoseBlockMinus(camera, camera_lin.data()); }
};

// Keys of the graph's variables in linear factors (backend/linear_elimination.h) and in the exact
// smoother's prior: a camera by its frame, a point or a motion by its variable id.
enum class VariableKind { kCamera = 0, kPoint = 1, kMotion = 2 };
inline int VariableKey(VariableKind kind, int id) { return 3 * id + static_cast<int>(kind); }
inline VariableKind KindOfKey(int key) { return static_cast<VariableKind>(key % 3); }
inline int IdOfKey(int key) { return key / 3; }
inline int TangentDimOfKey(int key) { return KindOfKey(key) == VariableKind::kPoint ? 3 : 6; }
inline int ValueSizeOfKey(int key) { return KindOfKey(key) == VariableKind::kPoint ? 3 : kPoseBlockSize; }

// What the frames that left the exact fixed-lag smoother's window say about the variables still in it
// (backend/exact_marginalisation.h): whitened rows r = r0 + R [x_1 (-) lin_1; x_2 (-) lin_2; ...] over
// `keys`, in that order (a camera or a motion 6 columns, [dt; phi] as the solvers' tangent; a point 3).
// Each variable keeps its linearisation point while it is in the prior (first-estimate Jacobians): R is
// not re-evaluated, only the tangent moves.
struct DensePrior {
  std::vector<int> keys;
  std::vector<std::vector<double>> lin;  // per key: a pose block (7 values) or a point (3)
  Eigen::MatrixXd R;
  Eigen::VectorXd r0;

  // The tangent of `value` (the key's current block) from the key's linearisation point.
  static Eigen::VectorXd Tangent(int key, const double* value, const double* lin) {
    if (KindOfKey(key) == VariableKind::kPoint)
      return Eigen::Vector3d(value[0] - lin[0], value[1] - lin[1], value[2] - lin[2]);
    return PoseBlockMinus(value, lin);
  }
};

struct FrameFactors {
  std::optional<OdometryEntry> odometry;  // links frame k-1 and k
  std::vector<PointMeasurementEntry> measurements;
  std::vector<PointMotionEntry> point_motions;
  std::vector<SmoothnessEntry> smoothness;
  std::vector<LinearPointFactor> linear_factors;  // from object points at k-1 that left the object window
};

// One object over one frame transition k-1 -> k, as the builder decided it.
struct ObjectTransition {
  int object_id = 0;
  int frame = 0;            // k
  bool is_dynamic = true;   // false: the object was static over k-1 -> k, H = identity
  int motion_var = -1;      // -1 when static or when no motion could be initialised
  std::vector<int> prev_point_vars;  // the inlier tracks' variables at k-1 (centroid c_{k-1})
  // Set once the variables at k-1 leave the smoother's window (their final centroid).
  std::optional<Vec3> centroid_prev_world;
  ReportedMotion reported = ReportedMotion::kMoving;  // ObjectObservation::reported
  // The time from frame k-1 to k by the frames' stamps; 0 when they carry none (the nominal frame period
  // then). More than one period when frames were dropped in between (serve when it falls behind).
  double step_s = 0.0;
  // What the measurement at k says of where the object is (carried to the results, not estimated): the
  // centroid of its measured points in camera k, and its box in image k when the source gives one.
  Vec3 centroid_camera = Vec3::Zero();
  std::optional<ImageBox> image_box;

  // Whether the transition's motion reaches the result sinks: it has an estimate and is supported.
  bool reportable() const { return !(is_dynamic && motion_var < 0) && reported != ReportedMotion::kUnsupported; }
};

inline SE3 MotionVariable::worldMotion() const {
  const SE3 H = BlockToPose(H_anchor.data());
  return SE3(H.rotation(), H.translation() + anchor_world - H.rotation() * anchor_world);
}

inline PoseBlock MotionVariable::AnchorBlock(const SE3& H_world, const Vec3& anchor_world) {
  PoseBlock block;
  PoseToBlock(SE3(H_world.rotation(), H_world.translation() + H_world.rotation() * anchor_world - anchor_world),
              block.data());
  return block;
}

// Sums of an object's smoothness residuals whitened by the configured sigmas, split into translation and
// rotation (backend/process_noise.h).
struct SmoothnessResiduals {
  double sum_sq_t = 0.0;
  double sum_sq_r = 0.0;
  int count = 0;
};

// One object's motion-smoothness process noise: the scales of its configured sigmas, and the residuals of
// its smoothness factors that are final (they left the smoother's window).
struct SmoothnessNoise {
  double scale_t = 1.0;
  double scale_r = 1.0;
  SmoothnessResiduals final;
};

// Variables keyed by ids that are never reused, so that the fixed-lag smoother can retire what left
// its window (memory bounded by the window, not the sequence) while the batch schedule keeps it all.
// Frames (camera poses, factors, transitions) retire from the front: frame k is stored at
// k - first_stored_frame.
struct FactorGraph {
  std::unordered_map<int, PointVariable> points;
  std::unordered_map<int, MotionVariable> motions;
  std::deque<PoseBlock> camera_poses;  // T_world_camera per stored frame
  std::deque<FrameFactors> frames;
  std::deque<ObjectTransition> transitions;  // in frame order
  int first_stored_frame = 0;
  int next_point_id = 0;
  int next_motion_id = 0;
  SE3 T_world_camera0_prior;
  Vec6 prior_sigma = Vec6::Constant(1e-4);
  std::optional<CameraPrior> camera_prior;  // on the window's first camera, once cameras have left it
  std::optional<DensePrior> dense_prior;    // the exact smoother's, once frames have left its window
  std::unordered_map<int, SmoothnessNoise> smoothness_noise;  // by object id; absent: scale 1

  int numFrames() const { return first_stored_frame + static_cast<int>(frames.size()); }
  double* camera(int k) { return camera_poses[k - first_stored_frame].data(); }
  const double* camera(int k) const { return camera_poses[k - first_stored_frame].data(); }
  FrameFactors& frame(int k) { return frames[k - first_stored_frame]; }
  const FrameFactors& frame(int k) const { return frames[k - first_stored_frame]; }
  // Drops every stored frame before k (their variables must have been retired or marginalised).
  void retireFramesBefore(int k) {
    while (first_stored_frame < k && !frames.empty()) {
      frames.pop_front();
      camera_poses.pop_front();
      ++first_stored_frame;
    }
  }
};

}  // namespace dslam
