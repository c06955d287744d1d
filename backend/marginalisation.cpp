#include "backend/marginalisation.h"

#include <Eigen/Cholesky>

#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "backend/factors/analytic_jacobians.h"
#include "backend/factors/huber_loss.h"
#include "backend/factors/pose_block.h"
#include "geometry/velocity.h"

namespace dslam {
namespace {

std::optional<Vec3> Centroid(const FactorGraph& graph, const std::vector<int>& vars) {
  Vec3 sum = Vec3::Zero();
  int n = 0;
  for (int v : vars) {
    const auto it = graph.points.find(v);
    if (it == graph.points.end()) continue;
    sum += it->second.position();
    ++n;
  }
  if (n == 0) return std::nullopt;
  return sum / static_cast<double>(n);
}

// Information of a camera's measurement of a point, camera held at its estimate: the measurement is
// linear in the point, r = W (R^T (l - t) - z), so it is exactly the Gaussian N(t + R z, (R W^2 R^T)^-1).
Mat3 MeasurementInformation(const Mat3& R, const Vec3& t, const PointMeasurementEntry& m, const Vec3& p_world,
                            const HuberLoss& huber) {
  Mat3 J_point;
  const Vec3 r = PointMeasurementResidual(R, t, p_world, m.z_camera, m.sigma_m.cwiseInverse(), nullptr, &J_point);
  return huber.weight(r.squaredNorm()) * J_point.transpose() * J_point;
}

}  // namespace

ObjectMotionEstimate MotionEstimateOf(const FactorGraph& graph, const ObjectTransition& tr, double frame_rate_hz) {
  ObjectMotionEstimate m;
  m.object_id = tr.object_id;
  m.frame = tr.frame;
  m.is_dynamic = tr.is_dynamic;
  if (tr.is_dynamic) m.H_world = graph.motions.at(tr.motion_var).worldMotion();
  const std::optional<Vec3> centroid = tr.centroid_prev_world ? tr.centroid_prev_world : Centroid(graph, tr.prev_point_vars);
  m.centroid_prev_world = centroid.value_or(Vec3::Zero());
  m.velocity_world_per_frame = tr.is_dynamic ? ObjectVelocityPerFrame(m.H_world, m.centroid_prev_world) : Vec3::Zero();
  m.speed_mps = SpeedMps(m.velocity_world_per_frame, frame_rate_hz);
  return m;
}

void MarginaliseObjectFrame(const BackendParams& params, double frame_rate_hz, int m, FactorGraph* graph,
                            EstimateSink* sink) {
  const HuberLoss huber{params.noise.huber_delta};
  const double* cam = graph->camera(m);
  const Mat3 R = BlockRotationMatrix(cam);
  const Vec3 t = BlockTranslation(cam);
  FrameFactors& fm = graph->frame(m);

  // The transitions into m+1 start from the points at m: their centroid is final now.
  for (auto& tr : graph->transitions)
    if (tr.frame == m + 1 && !tr.centroid_prev_world) tr.centroid_prev_world = Centroid(*graph, tr.prev_point_vars);

  // Information of each object point whose last measurement is at m (camera and motion at their estimates).
  std::unordered_map<int, Mat3> information;
  for (const auto& e : fm.measurements) {
    const PointVariable& var = graph->points.at(e.point_var);
    if (var.object_id < 0 || var.last_frame != m) continue;
    auto [it, is_new] = information.try_emplace(e.point_var, var.prior_info);
    it->second += MeasurementInformation(R, t, e, var.position(), huber);
  }
  const double inv_motion_sigma = 1.0 / params.noise.motion_sigma_m;
  for (const auto& pm : fm.point_motions) {
    const auto it = information.find(pm.curr_point_var);
    if (it == information.end()) continue;
    const MotionVariable& H = graph->motions.at(pm.motion_var);
    const Mat3 S = pm.prev_point_var >= 0 ? Mat3(Mat3::Identity() * inv_motion_sigma) : pm.sqrt_info;
    const Vec3 prev = pm.prev_point_var >= 0 ? graph->points.at(pm.prev_point_var).position() : pm.prev_mean_world;
    const Vec3 r = PointMotionResidual(BlockRotationMatrix(H.H_anchor.data()), BlockTranslation(H.H_anchor.data()),
                                       H.anchor_world, prev, graph->points.at(pm.curr_point_var).position(), S, nullptr,
                                       nullptr, nullptr);
    it->second += huber.weight(r.squaredNorm()) * S.transpose() * S;
  }

  // Their successors' ternary factors become binary factors with the marginal folded into the noise.
  if (m + 1 < graph->numFrames()) {
    const double motion_var_sq = params.noise.motion_sigma_m * params.noise.motion_sigma_m;
    for (auto& pm : graph->frame(m + 1).point_motions) {
      if (pm.prev_point_var < 0) continue;
      const auto it = information.find(pm.prev_point_var);
      if (it == information.end()) continue;
      const Mat3 cov_prev = it->second.ldlt().solve(Mat3::Identity());
      const Mat3 R_H = BlockRotationMatrix(graph->motions.at(pm.motion_var).H_anchor.data());
      const Mat3 cov = motion_var_sq * Mat3::Identity() + R_H * cov_prev * R_H.transpose();
      const Eigen::LLT<Mat3> llt(cov.inverse());
      pm.prev_mean_world = graph->points.at(pm.prev_point_var).position();
      pm.sqrt_info = llt.matrixU();
      pm.prev_point_var = -1;
    }
  }

  // Per-frame object points leave with their frame; points shared over frames (an object that was
  // static) stay until the camera window lets their measurements go.
  std::vector<PointMeasurementEntry> kept;
  kept.reserve(fm.measurements.size());
  for (const auto& e : fm.measurements) {
    const PointVariable& var = graph->points.at(e.point_var);
    if (var.object_id >= 0 && var.first_frame == m && var.last_frame == m) {
      sink->pointFinal({m, var.track_id, var.object_id, var.position()});
      graph->points.erase(e.point_var);
    } else {
      kept.push_back(e);
    }
  }
  fm.measurements.swap(kept);
  fm.point_motions.clear();
  fm.smoothness.clear();

  while (!graph->transitions.empty() && graph->transitions.front().frame <= m) {
    const ObjectTransition& tr = graph->transitions.front();
    if (!(tr.is_dynamic && tr.motion_var < 0)) sink->motionFinal(MotionEstimateOf(*graph, tr, frame_rate_hz));
    graph->transitions.pop_front();
  }
  if (m + 1 < graph->numFrames()) {
    for (auto& s : graph->frame(m + 1).smoothness) {
      if (s.prev_motion_var < 0 || graph->motions.at(s.prev_motion_var).last_frame > m) continue;
      const MotionVariable& prev = graph->motions.at(s.prev_motion_var);
      s.prev_fixed = prev.H_anchor;
      s.prev_fixed_anchor = prev.anchor_world;
      s.prev_motion_var = -1;
    }
  }
  for (auto it = graph->motions.begin(); it != graph->motions.end();)
    it = it->second.last_frame <= m ? graph->motions.erase(it) : std::next(it);
}

void MarginaliseCameraFrame(const BackendParams& params, int m, FactorGraph* graph, EstimateSink* sink) {
  const HuberLoss huber{params.noise.huber_delta};
  const double* cam = graph->camera(m);
  const Mat3 R = BlockRotationMatrix(cam);
  const Vec3 t = BlockTranslation(cam);
  FrameFactors& fm = graph->frame(m);
  std::unordered_set<int> ended;
  for (const auto& e : fm.measurements) {
    PointVariable& var = graph->points.at(e.point_var);
    sink->pointFinal({m, var.track_id, var.object_id, var.position()});
    if (var.last_frame <= m) {
      ended.insert(e.point_var);
      continue;
    }
    const Mat3 info = MeasurementInformation(R, t, e, var.position(), huber);
    var.prior_info += info;
    var.prior_info_vec += info * (t + R * e.z_camera);
  }
  for (int v : ended) graph->points.erase(v);
  fm = FrameFactors{fm.odometry, {}, {}, {}};
  sink->cameraFinal(m, BlockToPose(cam));
  graph->retireFramesBefore(m);
}

}  // namespace dslam
