#include "backend/exact_marginalisation.h"

#include <algorithm>
#include <deque>
#include <memory>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "backend/factors/analytic_jacobians.h"
#include "backend/factors/huber_loss.h"
#include "backend/factors/motion_smoothness_factor.h"
#include "backend/factors/odometry_factor.h"
#include "backend/factors/pose_factor_linearisation.h"
#include "backend/factors/pose_prior_factor.h"
#include "backend/linear_elimination.h"
#include "backend/marginalisation.h"
#include "backend/process_noise.h"

namespace dslam {
namespace {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

int CameraKey(int frame) { return VariableKey(VariableKind::kCamera, frame); }
int PointKey(int id) { return VariableKey(VariableKind::kPoint, id); }
int MotionKey(int id) { return VariableKey(VariableKind::kMotion, id); }

const double* ValueOf(const FactorGraph& graph, int key) {
  switch (KindOfKey(key)) {
    case VariableKind::kCamera: return graph.camera(IdOfKey(key));
    case VariableKind::kPoint: return graph.points.at(IdOfKey(key)).p_world.data();
    case VariableKind::kMotion: return graph.motions.at(IdOfKey(key)).H_anchor.data();
  }
  return nullptr;
}

// Which factors leave: those filed at frame m or before (their frame leaves; with the cameras held, a
// measurement of a landmark that stays is a factor on it alone) and those that touch a leaving variable.
// A camera is a variable only when the cameras are not held.
struct Touch {
  const std::unordered_set<int>& leaving;
  int m;
  bool cameras_fixed;

  bool camera(int frame) const { return !cameras_fixed && leaving.count(CameraKey(frame)); }
  bool point(int id) const { return leaving.count(PointKey(id)) > 0; }
  bool motion(int id) const { return id >= 0 && leaving.count(MotionKey(id)); }
  bool measurement(int frame, const PointMeasurementEntry& e) const {
    return frame <= m || camera(frame) || point(e.point_var);
  }
  bool pointMotion(int frame, const PointMotionEntry& e) const {
    return frame <= m || point(e.prev_point_var) || point(e.curr_point_var) || motion(e.motion_var);
  }
  bool smoothness(int frame, const SmoothnessEntry& s) const {
    return frame <= m || motion(s.prev_motion_var) || motion(s.curr_motion_var);
  }
  bool odometry(int frame) const { return frame <= m || camera(frame - 1) || camera(frame); }
};

// Linearised factors, each moved to its keys' reference points (a key in the prior: its linearisation
// point there; any other: its current value, where the factor is linearised).
class Rows {
 public:
  Rows(const FactorGraph& graph, bool cameras_fixed) : graph_(graph), cameras_fixed_(cameras_fixed) {
    if (!graph.dense_prior) return;
    for (size_t i = 0; i < graph.dense_prior->keys.size(); ++i)
      reference_[graph.dense_prior->keys[i]] = graph.dense_prior->lin[i].data();
  }

  // r + J d about the current values, moved to the reference points: r - J (x (-) reference).
  void add(const std::vector<int>& keys, const std::vector<MatX>& blocks, VecX r) {
    JacobianFactor f;
    for (size_t i = 0; i < keys.size(); ++i) {
      if (cameras_fixed_ && KindOfKey(keys[i]) == VariableKind::kCamera) continue;  // held: a constant
      const auto it = reference_.find(keys[i]);
      if (it != reference_.end()) r -= blocks[i] * DensePrior::Tangent(keys[i], ValueOf(graph_, keys[i]), it->second);
      f.keys.push_back(keys[i]);
      f.blocks.push_back(blocks[i]);
    }
    f.residual = std::move(r);
    if (!f.keys.empty()) factors_.push_back(std::move(f));
  }

  // The prior itself, already about its linearisation points: its rows at x = lin.
  void addPrior(const DensePrior& prior) {
    JacobianFactor f;
    int col = 0;
    for (int key : prior.keys) {
      const int dim = TangentDimOfKey(key);
      f.keys.push_back(key);
      f.blocks.push_back(prior.R.middleCols(col, dim));
      col += dim;
    }
    f.residual = prior.r0;
    factors_.push_back(std::move(f));
  }

  std::vector<JacobianFactor> take() { return std::move(factors_); }
  // A key's reference point: where the new prior is linearised for it.
  const double* reference(int key) const {
    const auto it = reference_.find(key);
    return it != reference_.end() ? it->second : ValueOf(graph_, key);
  }

 private:
  const FactorGraph& graph_;
  bool cameras_fixed_;
  std::unordered_map<int, const double*> reference_;
  std::vector<JacobianFactor> factors_;
};

// A pose factor's rows; a block whose key is -1 is held (no columns).
void AddPoseFactor(const ceres::CostFunction& cost, const std::vector<int>& keys,
                   const std::vector<const double*>& values, const HuberLoss* robust, Rows* rows) {
  Mat6 J[2];
  Mat6* wanted[2] = {keys[0] >= 0 ? &J[0] : nullptr, keys.size() > 1 && keys[1] >= 0 ? &J[1] : nullptr};
  const Vec6 r = LinearisePoseFactor(cost, values.data(), wanted);
  const double w = robust ? robust->sqrtWeight(r.squaredNorm()) : 1.0;
  std::vector<int> live;
  std::vector<MatX> blocks;
  for (size_t i = 0; i < keys.size(); ++i)
    if (keys[i] >= 0) live.push_back(keys[i]), blocks.push_back(w * J[i]);
  rows->add(live, blocks, w * r);
}

void AddFactors(const BackendParams& params, const FactorGraph& graph, const Touch& touch, Rows* rows) {
  const HuberLoss huber{params.noise.huber_delta};
  std::optional<HuberLoss> smoothness_huber;
  if (params.noise.smoothness_huber_delta > 0.0) smoothness_huber = HuberLoss{params.noise.smoothness_huber_delta};
  const Mat3 motion_whitening = Mat3::Identity() / params.noise.motion_sigma_m;
  if (graph.first_stored_frame == 0 && touch.camera(0) && graph.numFrames() > 0) {
    const std::unique_ptr<ceres::CostFunction> prior(
        PosePriorFactor::Create(graph.T_world_camera0_prior, graph.prior_sigma));
    AddPoseFactor(*prior, {CameraKey(0)}, {graph.camera(0)}, nullptr, rows);
  }
  for (int k = graph.first_stored_frame; k < graph.numFrames(); ++k) {
    const FrameFactors& f = graph.frame(k);
    if (f.odometry && k > graph.first_stored_frame && touch.odometry(k)) {
      const std::unique_ptr<ceres::CostFunction> cost(
          OdometryFactor::Create(f.odometry->T_prev_curr, f.odometry->sigma));
      AddPoseFactor(*cost, {CameraKey(k - 1), CameraKey(k)}, {graph.camera(k - 1), graph.camera(k)}, nullptr, rows);
    }
    const double* cam = graph.camera(k);
    for (const auto& e : f.measurements) {
      if (!touch.measurement(k, e)) continue;
      Mat36 J_camera;
      Mat3 J_point;
      const Vec3 r = PointMeasurementResidual(BlockRotationMatrix(cam), BlockTranslation(cam),
                                              graph.points.at(e.point_var).position(), e.z_camera,
                                              e.sigma_m.cwiseInverse(), &J_camera, &J_point);
      const double w = huber.sqrtWeight(r.squaredNorm());
      rows->add({CameraKey(k), PointKey(e.point_var)}, {w * J_camera, w * J_point}, w * r);
    }
    for (const auto& e : f.point_motions) {
      if (!touch.pointMotion(k, e)) continue;
      const MotionVariable& H = graph.motions.at(e.motion_var);
      Mat3 J_prev, J_curr;
      Mat36 J_motion;
      const Vec3 r = PointMotionResidual(BlockRotationMatrix(H.H_anchor.data()), BlockTranslation(H.H_anchor.data()),
                                         H.anchor_world, graph.points.at(e.prev_point_var).position(),
                                         graph.points.at(e.curr_point_var).position(), motion_whitening, &J_prev,
                                         &J_curr, &J_motion);
      const double w = huber.sqrtWeight(r.squaredNorm());
      rows->add({PointKey(e.prev_point_var), PointKey(e.curr_point_var), MotionKey(e.motion_var)},
                {w * J_prev, w * J_curr, w * J_motion}, w * r);
    }
    for (const auto& s : f.smoothness) {
      if (!touch.smoothness(k, s)) continue;
      const MotionVariable& curr = graph.motions.at(s.curr_motion_var);
      const bool prev_live = s.prev_motion_var >= 0;
      const Vec3 anchor_prev = prev_live ? graph.motions.at(s.prev_motion_var).anchor_world : s.prev_fixed_anchor;
      const std::unique_ptr<ceres::CostFunction> cost(MotionSmoothnessFactor::Create(
          SmoothnessSigma(params, graph, curr.object_id), anchor_prev, curr.anchor_world));
      const double* prev = prev_live ? graph.motions.at(s.prev_motion_var).H_anchor.data() : s.prev_fixed.data();
      AddPoseFactor(*cost, {prev_live ? MotionKey(s.prev_motion_var) : -1, MotionKey(s.curr_motion_var)},
                    {prev, curr.H_anchor.data()}, smoothness_huber ? &*smoothness_huber : nullptr, rows);
    }
    if (!f.linear_factors.empty())
      throw std::logic_error("exact marginalisation: frame " + std::to_string(k) +
                             " holds linear factors of the sparsified window");
  }
  // Priors the sparsified window left on a landmark (none in an exact run), as rows at its estimate.
  for (const auto& [id, p] : graph.points) {
    if (!touch.point(id) || !p.hasPrior()) continue;
    const JacobianFactor prior = PointPriorRows(PointKey(id), p, huber);
    rows->add(prior.keys, prior.blocks, prior.residual);
  }
}

}  // namespace

std::vector<int> LeavingKeys(const FactorGraph& graph, int m, bool cameras_fixed) {
  std::vector<int> keys;
  if (!cameras_fixed) keys.push_back(CameraKey(m));
  for (const auto& [id, p] : graph.points)
    if (p.last_frame <= m) keys.push_back(PointKey(id));
  for (const auto& [id, h] : graph.motions)
    if (h.last_frame <= m) keys.push_back(MotionKey(id));
  std::sort(keys.begin(), keys.end());
  return keys;
}

void MarginaliseFrameExactly(const BackendParams& params, double frame_rate_hz, int m, bool cameras_fixed,
                             FactorGraph* graph, EstimateSink* sink) {
  if (graph->first_stored_frame != m)
    throw std::logic_error("exact marginalisation: frame " + std::to_string(m) + " leaves, but the window starts at " +
                           std::to_string(graph->first_stored_frame));
  const std::vector<int> leaving = LeavingKeys(*graph, m, cameras_fixed);
  const std::unordered_set<int> leaving_set(leaving.begin(), leaving.end());
  const Touch touch{leaving_set, m, cameras_fixed};

  // The new prior, about the reference points.
  Rows rows(*graph, cameras_fixed);
  AddFactors(params, *graph, touch, &rows);
  if (graph->dense_prior) rows.addPrior(*graph->dense_prior);
  std::vector<JacobianFactor> factors = rows.take();
  std::optional<DensePrior> prior;
  if (!factors.empty()) {
    GaussianMarginal marginal;
    try {
      marginal = MarginaliseBySchur(factors, leaving);
    } catch (const std::runtime_error&) {
      // A leaving variable its factors do not determine (a motion all of whose point pairs were outliers):
      // a whisper of information on each leaving variable determines it without moving what stays.
      constexpr double kWhisper = 1e-6;
      for (int key : leaving) {
        const int dim = TangentDimOfKey(key);
        factors.push_back({{key}, {kWhisper * MatX::Identity(dim, dim)}, VecX::Zero(dim)});
      }
      marginal = MarginaliseBySchur(factors, leaving);
    }
    if (marginal.dimension() > 0) {
      const SquareRootRows square_root = SquareRootOf(marginal);
      DensePrior p;
      p.keys = marginal.keys;
      p.R = square_root.R;
      p.r0 = square_root.r;
      for (int key : p.keys) {
        const double* ref = rows.reference(key);
        p.lin.emplace_back(ref, ref + ValueSizeOfKey(key));
      }
      prior = std::move(p);
    }
  }

  // What became final, before its variables go.
  for (ObjectTransition& tr : graph->transitions) {
    if (tr.centroid_prev_world) continue;
    const bool leaves = std::any_of(tr.prev_point_vars.begin(), tr.prev_point_vars.end(),
                                    [&](int v) { return touch.point(v); });
    if (leaves) tr.centroid_prev_world = Centroid(*graph, tr.prev_point_vars);
  }
  std::deque<ObjectTransition> kept_transitions;
  for (ObjectTransition& tr : graph->transitions) {
    if (tr.frame <= m && (tr.motion_var < 0 || touch.motion(tr.motion_var))) {
      if (tr.reportable()) sink->motionFinal(MotionEstimateOf(*graph, tr, frame_rate_hz));
      continue;
    }
    if (tr.centroid_prev_world) tr.prev_point_vars = {};  // those points are gone or going
    kept_transitions.push_back(std::move(tr));
  }
  graph->transitions.swap(kept_transitions);
  for (const auto& e : graph->frame(m).measurements) {
    const PointVariable& var = graph->points.at(e.point_var);
    sink->pointFinal({m, var.track_id, var.object_id, var.position()});
  }
  sink->cameraFinal(m, BlockToPose(graph->camera(m)));

  // The eliminated factors and variables go; the prior replaces them.
  for (int k = graph->first_stored_frame; k < graph->numFrames(); ++k) {
    FrameFactors& f = graph->frame(k);
    if (f.odometry && k > graph->first_stored_frame && touch.odometry(k)) f.odometry.reset();
    f.measurements.erase(std::remove_if(f.measurements.begin(), f.measurements.end(),
                                        [&](const PointMeasurementEntry& e) { return touch.measurement(k, e); }),
                         f.measurements.end());
    f.point_motions.erase(std::remove_if(f.point_motions.begin(), f.point_motions.end(),
                                         [&](const PointMotionEntry& e) { return touch.pointMotion(k, e); }),
                          f.point_motions.end());
    auto leaving_smoothness = [&](const SmoothnessEntry& s) {
      if (!touch.smoothness(k, s)) return false;
      AccumulateFinalSmoothness(params, s, graph);
      return true;
    };
    f.smoothness.erase(std::remove_if(f.smoothness.begin(), f.smoothness.end(), leaving_smoothness),
                       f.smoothness.end());
  }
  for (int key : leaving) {
    if (KindOfKey(key) == VariableKind::kPoint) graph->points.erase(IdOfKey(key));
    if (KindOfKey(key) == VariableKind::kMotion) graph->motions.erase(IdOfKey(key));
  }
  ForgetObjectsWithoutMotions(graph);
  graph->dense_prior = std::move(prior);
  graph->retireFramesBefore(m + 1);
}

}  // namespace dslam
