#include "backend/graph_builder.h"

#include <cmath>
#include <stdexcept>

#include "backend/factors/pose_block.h"

namespace dslam {
namespace {
// Where the measurement puts the object, carried to its results.
void DescribeFromMeasurement(const ObjectObservation& obs, ObjectTransition* transition) {
  Vec3 sum = Vec3::Zero();
  for (const PointObservation& p : obs.points) sum += p.p_camera;
  if (!obs.points.empty()) transition->centroid_camera = sum / static_cast<double>(obs.points.size());
  transition->image_box = obs.image_box;
}

// Whether two motions span the same time (within 10 %: a camera's stamps jitter by a few percent), so that
// a motion model may tie them. A step of 0 is unknown (frames without stamps): taken as the same.
bool SameStep(double a_s, double b_s) { return a_s <= 0.0 || b_s <= 0.0 || std::abs(a_s - b_s) <= 0.1 * std::max(a_s, b_s); }
}  // namespace

GraphBuilder::GraphBuilder(const BackendParams& params, const BuilderOptions& options, FactorGraph* graph)
    : params_(params), options_(options), graph_(graph) {
  graph_->prior_sigma = Vec6::Constant(params.noise.prior_sigma);
}

Vec3 GraphBuilder::pointSigma(const Vec3& z_camera) const {
  // Depth noise (stereo: sigma_z = sigma_disparity * z^2 / (fx * b)) lies along the viewing ray, so it moves
  // x and y by x/z and y/z of it: per axis, the diagonal of that covariance.
  const double depth = z_camera.z(), along_ray = params_.noise.point_sigma_per_depth_sq * depth * depth;
  const double lateral_x = depth > 0.0 ? std::abs(z_camera.x() / depth) : 0.0;
  const double lateral_y = depth > 0.0 ? std::abs(z_camera.y() / depth) : 0.0;
  return (Vec3(lateral_x, lateral_y, 1.0) * along_ray).array() + params_.noise.point_sigma_m;
}

int GraphBuilder::newPointVariable(const Vec3& p_world, int64_t track_id, int object_id, int frame, int prev_var) {
  PointVariable var;
  var.p_world = {p_world.x(), p_world.y(), p_world.z()};
  var.track_id = track_id;
  var.object_id = object_id;
  var.first_frame = frame;
  var.last_frame = frame;
  var.eliminate_first = prev_var < 0 ? true : !graph_->points.at(prev_var).eliminate_first;
  const int id = graph_->next_point_id++;
  graph_->points.emplace(id, var);
  return id;
}

void GraphBuilder::addMeasurement(int frame, int point_var, const Vec3& z_camera, double extra_variance_m2) {
  graph_->points.at(point_var).last_frame = frame;
  Vec3 sigma = pointSigma(z_camera);
  if (extra_variance_m2 > 0.0) sigma = (sigma.array().square() + extra_variance_m2).sqrt().matrix();
  graph_->frame(frame).measurements.push_back({point_var, z_camera, sigma});
}

void GraphBuilder::addFrame(const FrameMeasurement& frame, const SE3* T_world_camera_init) {
  const int k = graph_->numFrames();
  if (const std::string bad = FindInvalidMeasurement(frame, k); !bad.empty()) throw std::invalid_argument(bad);

  SE3 T_world_camera;
  if (T_world_camera_init) {
    T_world_camera = *T_world_camera_init;
  } else if (k == 0) {
    T_world_camera = graph_->T_world_camera0_prior;
  } else {
    T_world_camera = BlockToPose(graph_->camera(k - 1));
    if (frame.camera_motion_guess)
      T_world_camera = T_world_camera * *frame.camera_motion_guess;
    else if (frame.odometry)
      T_world_camera = T_world_camera * frame.odometry->T_prev_curr;
  }
  // The time since the previous frame, by the stamps; 0 (unknown) when they do not increase.
  const double step_s =
      k > 0 && last_t_ns_ && frame.t_ns > *last_t_ns_ ? 1e-9 * static_cast<double>(frame.t_ns - *last_t_ns_) : 0.0;
  last_t_ns_ = frame.t_ns;
  graph_->camera_poses.emplace_back();
  PoseToBlock(T_world_camera, graph_->camera_poses.back().data());
  graph_->frames.emplace_back();
  FrameFactors& factors = graph_->frames.back();

  if (k > 0 && frame.odometry && options_.use_odometry)
    factors.odometry = OdometryEntry{frame.odometry->T_prev_curr, frame.odometry->sigma};

  if (options_.use_static_points) {
    for (const auto& obs : frame.static_points) {
      auto [it, is_new] = static_track_to_var_.try_emplace(obs.track_id, -1);
      // A landmark retired by the smoother (unseen for a whole window) starts a new variable.
      if (!is_new && !graph_->points.count(it->second)) is_new = true;
      if (is_new) it->second = newPointVariable(T_world_camera * obs.p_camera, obs.track_id, -1, k, -1);
      addMeasurement(k, it->second, obs.p_camera);
    }
  }
  if (options_.use_objects)
    for (const auto& obs : frame.objects) addObject(obs, k, step_s, T_world_camera);
  forgetRetired(k);
}

void GraphBuilder::forgetRetired(int frame) {
  // A sweep every 32 frames: the maps hold what the graph still refers to plus 32 frames of new tracks.
  if (frame % 32 != 0) return;
  for (auto it = static_track_to_var_.begin(); it != static_track_to_var_.end();)
    it = graph_->points.count(it->second) ? std::next(it) : static_track_to_var_.erase(it);
  // An object not seen at the newest frame whose motions are all retired starts afresh if it returns,
  // which is what its stale state would lead to anyway.
  for (auto it = objects_.begin(); it != objects_.end();) {
    const ObjectTrackState& s = it->second;
    const bool stale = s.last_frame < frame && !graph_->motions.count(s.constant_motion_var) &&
                       !graph_->motions.count(s.last_motion_var);
    it = stale ? objects_.erase(it) : std::next(it);
  }
}

void GraphBuilder::addObject(const ObjectObservation& obs, int frame, double step_s, const SE3& T_world_camera) {
  ObjectTrackState& state = objects_[obs.object_id];
  const bool consecutive = state.last_frame == frame - 1;
  std::vector<int> prev_vars(obs.points.size(), -1), curr_vars(obs.points.size(), -1);
  for (size_t i = 0; i < obs.points.size(); ++i) {
    if (!consecutive) break;
    const auto it = state.track_to_var.find(obs.points[i].track_id);
    if (it != state.track_to_var.end()) prev_vars[i] = it->second;
  }

  if (consecutive && !obs.is_dynamic) {
    // Static over k-1 -> k: the object's points keep their variables and act as static structure.
    ObjectTransition transition;
    transition.object_id = obs.object_id;
    transition.frame = frame;
    transition.is_dynamic = false;
    transition.step_s = step_s;
    DescribeFromMeasurement(obs, &transition);
    for (size_t i = 0; i < obs.points.size(); ++i) {
      if (prev_vars[i] >= 0) {
        curr_vars[i] = prev_vars[i];
        transition.prev_point_vars.push_back(prev_vars[i]);
      } else {
        curr_vars[i] = newPointVariable(T_world_camera * obs.points[i].p_camera, obs.points[i].track_id,
                                        obs.object_id, frame, -1);
      }
    }
    graph_->transitions.push_back(std::move(transition));
    state.last_motion_var = -1;
  } else {
    for (size_t i = 0; i < obs.points.size(); ++i)
      curr_vars[i] = newPointVariable(T_world_camera * obs.points[i].p_camera, obs.points[i].track_id, obs.object_id,
                                      frame, prev_vars[i]);
    if (consecutive)
      addDynamicTransition(obs, frame, step_s, state, prev_vars, curr_vars);
    else
      state.last_motion_var = -1;
  }

  state.track_to_var.clear();
  // As static structure, a jittering object's points share one error: each point's variance grows by
  // N jitter variances, so the N together constrain the camera as one landmark of that jitter would.
  const double shared_variance_m2 = consecutive && !obs.is_dynamic
                                        ? static_cast<double>(obs.points.size()) * obs.jitter_sigma_m * obs.jitter_sigma_m
                                        : 0.0;
  for (size_t i = 0; i < obs.points.size(); ++i) {
    addMeasurement(frame, curr_vars[i], obs.points[i].p_camera, shared_variance_m2);
    state.track_to_var[obs.points[i].track_id] = curr_vars[i];
  }
  state.last_frame = frame;
}

void GraphBuilder::addDynamicTransition(const ObjectObservation& obs, int frame, double step_s, ObjectTrackState& state,
                                        const std::vector<int>& prev_vars, const std::vector<int>& curr_vars) {
  ObjectTransition transition;
  transition.object_id = obs.object_id;
  transition.frame = frame;
  transition.step_s = step_s;
  transition.reported = obs.reported;
  DescribeFromMeasurement(obs, &transition);
  std::vector<Vec3> src, dst;
  std::vector<size_t> pair_index;
  for (size_t i = 0; i < obs.points.size(); ++i) {
    if (prev_vars[i] < 0) continue;
    src.push_back(graph_->points.at(prev_vars[i]).position());
    dst.push_back(graph_->points.at(curr_vars[i]).position());
    pair_index.push_back(i);
  }
  const auto fit = InitialMotion(obs, frame, src, dst);
  if (!fit) {
    // Too few consistent tracks: no motion for this transition (it lowers coverage, not accuracy).
    graph_->transitions.push_back(std::move(transition));
    state.last_motion_var = -1;
    return;
  }

  FrameFactors& factors = graph_->frame(frame);
  const MotionMode mode = params_.modeFor(obs.object_id);
  // A motion model ties motions of equal time steps only: after dropped frames a motion spans several
  // periods, and held to the one before it would pull the cameras through the object's points.
  int motion_var = mode == MotionMode::kConstant && SameStep(state.constant_motion_step_s, step_s) ? state.constant_motion_var : -1;
  if (motion_var >= 0 && !graph_->motions.count(motion_var)) motion_var = -1;  // retired by the smoother
  if (motion_var < 0) {
    // Anchor: the centroid of the RANSAC inliers at k-1, a point on the object.
    Vec3 anchor = Vec3::Zero();
    for (size_t j = 0; j < src.size(); ++j)
      if (fit->is_inlier[j]) anchor += src[j];
    anchor /= static_cast<double>(fit->num_inliers);
    MotionVariable var;
    var.anchor_world = anchor;
    var.H_anchor = MotionVariable::AnchorBlock(fit->transform, anchor);
    var.object_id = obs.object_id;
    var.first_frame = frame;
    motion_var = graph_->next_motion_id++;
    graph_->motions.emplace(motion_var, var);
    if (mode == MotionMode::kConstant) state.constant_motion_var = motion_var, state.constant_motion_step_s = step_s;
  }
  graph_->motions.at(motion_var).last_frame = frame;
  if (mode == MotionMode::kSmoothed && state.last_motion_var >= 0 && SameStep(state.last_motion_step_s, step_s))
    factors.smoothness.push_back({state.last_motion_var, motion_var, {}, Vec3::Zero()});

  for (size_t j = 0; j < pair_index.size(); ++j) {
    if (!fit->is_inlier[j]) continue;
    const size_t i = pair_index[j];
    factors.point_motions.push_back({prev_vars[i], curr_vars[i], motion_var});
    transition.prev_point_vars.push_back(prev_vars[i]);
  }
  transition.motion_var = motion_var;
  graph_->transitions.push_back(std::move(transition));
  state.last_motion_var = motion_var;
  state.last_motion_step_s = step_s;
}

std::optional<RansacResult> GraphBuilder::InitialMotion(const ObjectObservation& obs, int frame,
                                                       const std::vector<Vec3>& src_world,
                                                       const std::vector<Vec3>& dst_world) const {
  if (obs.motion_fit) {
    // The image front-end's fit, moved from camera k-1 into the world at camera k-1's estimate, is the
    // hypothesis; its inliers are checked against the points' world estimates (the smoothed points at
    // k-1 reject tracks the front-end's raw depths let through) and H refitted on them.
    const SE3 T_world_prev = BlockToPose(graph_->camera(frame - 1));
    const SE3 H_world = T_world_prev * obs.motion_fit->H_camera_prev * T_world_prev.inverse();
    if (auto refined = RefineRigid(H_world, src_world, dst_world, params_.motion_ransac)) return refined;
  }
  RansacParams ransac = params_.motion_ransac;
  ransac.seed += static_cast<uint64_t>(frame) * 1000003u + static_cast<uint64_t>(obs.object_id);
  return AlignRigidRansac(src_world, dst_world, ransac);
}

}  // namespace dslam
