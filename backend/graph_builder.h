#pragma once
// Turns frames of measurements into variables, initial values and factors of the factor graph.

#include <map>
#include <optional>
#include <unordered_map>
#include <vector>

#include "backend/backend_params.h"
#include "backend/factor_graph.h"
#include "data/measurements.h"

namespace dslam {

struct BuilderOptions {
  bool use_static_points = true;
  bool use_objects = true;
  bool use_odometry = true;
};

class GraphBuilder {
 public:
  GraphBuilder(const BackendParams& params, const BuilderOptions& options, FactorGraph* graph);

  // Adds frame k = graph->numFrames(). The camera pose is initialised by composing the odometry with
  // the current estimate of frame k-1 (or from `T_world_camera_init` when given).
  // Throws std::invalid_argument on a frame index out of sequence or non-finite measurements.
  void addFrame(const FrameMeasurement& frame, const SE3* T_world_camera_init = nullptr);

  // Track and object identities the builder remembers; bounded by what the graph still holds (the
  // smoother retires variables, and the builder forgets what refers only to retired ones).
  size_t rememberedIdentities() const { return static_track_to_var_.size() + objects_.size(); }

 private:
  struct ObjectTrackState {
    int last_frame = -1;
    std::unordered_map<int64_t, int> track_to_var;  // variables at last_frame
    int last_motion_var = -1;                        // for smoothness, valid if made at last_frame
    int constant_motion_var = -1;                    // constant mode: the object's single H
    double last_motion_step_s = 0.0;                 // the time step each of those two motions spans
    double constant_motion_step_s = 0.0;
  };

  void forgetRetired(int frame);
  Vec3 pointSigma(const Vec3& z_camera) const;
  void addMeasurement(int frame, int point_var, const Vec3& z_camera, double extra_variance_m2 = 0.0);
  int newPointVariable(const Vec3& p_world, int64_t track_id, int object_id, int frame, int prev_var);
  void addObject(const ObjectObservation& obs, int frame, double step_s, const SE3& T_world_camera);
  void addDynamicTransition(const ObjectObservation& obs, int frame, double step_s, ObjectTrackState& state,
                            const std::vector<int>& prev_vars, const std::vector<int>& curr_vars);
  // The motion the transition's H starts from and the track pairs that get the ternary factor: the image
  // front-end's fit when it made one, else RANSAC on the points' world estimates.
  std::optional<RansacResult> InitialMotion(const ObjectObservation& obs, int frame, const std::vector<Vec3>& src_world,
                                            const std::vector<Vec3>& dst_world) const;

  const BackendParams& params_;
  BuilderOptions options_;
  FactorGraph* graph_;
  std::unordered_map<int64_t, int> static_track_to_var_;
  std::map<int, ObjectTrackState> objects_;
  std::optional<int64_t> last_t_ns_;  // the stamp of the last frame added
};

}  // namespace dslam
