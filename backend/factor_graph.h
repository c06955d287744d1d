#pragma once
// Storage of the factor graph: variables (plain double arrays Ceres optimises in place) and factors
// filed by the frame that introduced them, so a sliding window touches only its own frames.

#include <array>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "backend/factors/pose_block.h"
#include "geometry/se3.h"

namespace dslam {



struct PointVariable {
  std::array<double, 3> p_world{};
  int64_t track_id = 0;
  int object_id = -1;  // -1: static background structure
  int first_frame = 0;
  int last_frame = 0;  // last frame a factor refers to it; older than the window => held fixed
  // Schur elimination group: points linked by a motion factor alternate, so that the points of
  // the first group form an independent set, as Schur solvers require.
  bool eliminate_first = true;
  // (frame, index into that frame's measurements) of every observation, oldest first: the sliding
  // window re-uses a landmark's older observations, against fixed cameras, to keep it anchored.
  std::vector<std::pair<int, int>> observations;
};

// An object's pose change, stored about an anchor point c near the object (not about the world
// origin): H_world = Tc * H_anchor * Tc^-1 with Tc the translation by c. The same motion, but a small
// rotation no longer swings a translation the size of the object's distance from the origin, which
// would make the problem worse conditioned the farther a run goes.
struct MotionVariable {
  PoseBlock H_anchor{};
  Vec3 anchor_world = Vec3::Zero();
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

struct PointMotionEntry {
  int prev_point_var;
  int curr_point_var;
  int motion_var;
};

struct SmoothnessEntry {
  int prev_motion_var;
  int curr_motion_var;
};

struct FrameFactors {
  std::optional<OdometryEntry> odometry;  // links frame k-1 and k
  std::vector<PointMeasurementEntry> measurements;
  std::vector<PointMotionEntry> point_motions;
  std::vector<SmoothnessEntry> smoothness;
};

// One object over one frame transition k-1 -> k, as the builder decided it.
struct ObjectTransition {
  int object_id = 0;
  int frame = 0;            // k
  bool is_dynamic = true;   // false: the object was static over k-1 -> k, H = identity
  int motion_var = -1;      // -1 when static or when no motion could be initialised
  std::vector<int> prev_point_vars;  // the inlier tracks' variables at k-1 (centroid c_{k-1})
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

struct FactorGraph {
  std::vector<PoseBlock> camera_poses;  // T_world_camera per frame
  std::vector<PointVariable> points;
  std::vector<MotionVariable> motions;
  std::vector<FrameFactors> frames;
  std::vector<ObjectTransition> transitions;
  SE3 T_world_camera0_prior;
  Vec6 prior_sigma = Vec6::Constant(1e-4);

  int numFrames() const { return static_cast<int>(frames.size()); }
};

}  // namespace dslam
