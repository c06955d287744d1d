#include "backend/marginalisation.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include <algorithm>
#include <deque>
#include <memory>
#include <optional>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "backend/factors/analytic_jacobians.h"
#include "backend/factors/huber_loss.h"
#include "backend/factors/odometry_factor.h"
#include "backend/factors/pose_block.h"
#include "backend/factors/pose_factor_linearisation.h"
#include "backend/factors/pose_prior_factor.h"
#include "backend/linear_elimination.h"
#include "backend/process_noise.h"
#include "geometry/velocity.h"

namespace dslam {
namespace {

template <typename T, typename Pred>
void EraseIf(std::vector<T>& items, Pred pred) {
  items.erase(std::remove_if(items.begin(), items.end(), pred), items.end());
}

// The residual of a linear factor at the graph's current values.
Vec6 LinearFactorResidual(const FactorGraph& graph, const LinearPointFactor& lf) {
  return lf.residual(lf.camera_frame >= 0 ? graph.camera(lf.camera_frame) : nullptr,
                     graph.points.at(lf.point_var).position(), graph.motions.at(lf.motion_var).H_anchor.data());
}

}  // namespace

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

double SpeedSigmaMps(const MotionVariable& motion, const Vec3& centroid_prev_world, const Vec3& velocity_per_frame,
                     double frame_rate_hz) {
  // v = t_H + (I - R)(a - c) for the block (R, t_H) about the anchor a; perturbed by [dt; dphi] (dphi on
  // the right), dv = dt + R [a - c]x dphi. The centroid's own uncertainty is left out: its effect is
  // (I - R) times it, small for the rotations of a frame.
  const Mat3 R = BlockRotationMatrix(motion.H_anchor.data());
  Eigen::Matrix<double, 3, 6> J;
  J << Mat3::Identity(), R * Hat(motion.anchor_world - centroid_prev_world);
  const Mat3 cov_v = J * motion.covariance * J.transpose();
  const double speed = velocity_per_frame.norm();
  // Along the velocity; for a speed near zero (norm of a 3D Gaussian), the mean per-axis variance.
  const double var = speed > 1e-9 ? velocity_per_frame.dot(cov_v * velocity_per_frame) / (speed * speed)
                                  : cov_v.trace() / 3.0;
  return std::sqrt(std::max(0.0, var)) * frame_rate_hz;
}

ObjectMotionEstimate MotionEstimateOf(const FactorGraph& graph, const ObjectTransition& tr, double frame_rate_hz) {
  // Speeds per second of the transition's own step: after dropped frames its motion spans several periods.
  const double steps_per_s = tr.step_s > 0.0 ? 1.0 / tr.step_s : frame_rate_hz;
  ObjectMotionEstimate m;
  m.object_id = tr.object_id;
  m.frame = tr.frame;
  m.step_s = tr.step_s;
  // Reported as estimated only when the classifier calls it moving; a jittering parked car is estimated
  // with its own motion (so that it does not pull the camera) but reported standing.
  m.is_dynamic = tr.is_dynamic && tr.reported == ReportedMotion::kMoving;
  m.centroid_camera = tr.centroid_camera;
  m.image_box = tr.image_box;
  if (m.is_dynamic) m.H_world = graph.motions.at(tr.motion_var).worldMotion();
  const std::optional<Vec3> centroid = tr.centroid_prev_world ? tr.centroid_prev_world : Centroid(graph, tr.prev_point_vars);
  m.centroid_prev_world = centroid.value_or(Vec3::Zero());
  m.velocity_world_per_frame = m.is_dynamic ? ObjectVelocityPerFrame(m.H_world, m.centroid_prev_world) : Vec3::Zero();
  m.speed_mps = SpeedMps(m.velocity_world_per_frame, steps_per_s);
  if (m.is_dynamic) {
    const MotionVariable& motion = graph.motions.at(tr.motion_var);
    m.covariance = motion.covariance;
    m.anchor_world = motion.anchor_world;
    m.speed_sigma_mps = SpeedSigmaMps(motion, m.centroid_prev_world, m.velocity_world_per_frame, steps_per_s);
  }
  return m;
}

ObjectWindow ObjectWindowOf(const BackendParams& params, int object_id) {
  return params.modeFor(object_id) == MotionMode::kConstant ? ObjectWindow::kTrackMotion : ObjectWindow::kPerFrameMotion;
}

void MarginaliseObjectFrame(const BackendParams& params, double frame_rate_hz, int m, FactorGraph* graph,
                            EstimateSink* sink, ObjectWindow which) {
  const HuberLoss huber{params.noise.huber_delta};
  auto selected = [&](int object_id) {
    return object_id >= 0 && (which == ObjectWindow::kAll || ObjectWindowOf(params, object_id) == which);
  };
  const double* cam = graph->camera(m);
  const Mat3 R = BlockRotationMatrix(cam);
  const Vec3 t = BlockTranslation(cam);
  FrameFactors& fm = graph->frame(m);

  // The transitions into m+1 start from the points at m: their centroid is final now.
  for (auto& tr : graph->transitions)
    if (tr.frame == m + 1 && !tr.centroid_prev_world && selected(tr.object_id)) tr.centroid_prev_world = Centroid(*graph, tr.prev_point_vars);

  // Each object point whose last measurement is at m is marginalised. Its factors that involve only it
  // (its prior, the factor from its predecessor with the motion at its estimate, the linear factor its
  // predecessor left, with that camera and motion at their estimates) fold into one 3-row unary; with its
  // measurement (camera m) and the ternary factor to its successor, eliminating the point leaves a 6-row
  // linear factor on (camera m, successor, motion into m+1): the camera keeps the object's constraint.
  const double inv_motion_sigma = 1.0 / params.noise.motion_sigma_m;
  struct Unary {
    Mat3 info = Mat3::Zero();
    Vec3 gradient = Vec3::Zero();
  };
  std::unordered_map<int, Unary> unary;
  std::unordered_map<int, const PointMeasurementEntry*> measurement;
  for (const auto& e : fm.measurements) {
    const PointVariable& var = graph->points.at(e.point_var);
    if (!selected(var.object_id) || var.last_frame != m) continue;
    auto [it, is_new] = unary.try_emplace(e.point_var);
    if (is_new) var.priorNormalEquations(var.position(), huber, &it->second.info, &it->second.gradient);
    if (!measurement.emplace(e.point_var, &e).second) {
      // A second measurement at m (not made by the builder): camera held at its estimate.
      Mat3 J_point;
      const Vec3 r = PointMeasurementResidual(R, t, var.position(), e.z_camera, e.sigma_m.cwiseInverse(), nullptr, &J_point);
      const double w = huber.weight(r.squaredNorm());
      it->second.info += w * J_point.transpose() * J_point;
      it->second.gradient += w * J_point.transpose() * r;
    }
  }
  for (const auto& pm : fm.point_motions) {
    const auto it = unary.find(pm.curr_point_var);
    if (it == unary.end()) continue;
    const MotionVariable& H = graph->motions.at(pm.motion_var);
    const Mat3 S = Mat3::Identity() * inv_motion_sigma;
    const Vec3 prev = graph->points.at(pm.prev_point_var).position();
    Mat3 J_curr;
    const Vec3 r = PointMotionResidual(BlockRotationMatrix(H.H_anchor.data()), BlockTranslation(H.H_anchor.data()),
                                       H.anchor_world, prev, graph->points.at(pm.curr_point_var).position(), S, nullptr,
                                       &J_curr, nullptr);
    const double w = huber.weight(r.squaredNorm());
    it->second.info += w * J_curr.transpose() * J_curr;
    it->second.gradient += w * J_curr.transpose() * r;
  }
  for (const auto& lf : fm.linear_factors) {
    const auto it = unary.find(lf.point_var);
    if (it == unary.end()) continue;
    const Vec6 r = LinearFactorResidual(*graph, lf);
    const Eigen::Matrix<double, 6, 3> J_point = lf.J.middleCols<3>(6);
    it->second.info += J_point.transpose() * J_point;
    it->second.gradient += J_point.transpose() * r;
  }

  if (m + 1 < graph->numFrames()) {
    FrameFactors& next = graph->frame(m + 1);
    std::vector<PointMotionEntry> kept_motions;
    for (const auto& pm : next.point_motions) {
      const auto u = unary.find(pm.prev_point_var);
      const auto meas = u == unary.end() ? measurement.end() : measurement.find(pm.prev_point_var);
      if (meas == measurement.end()) {
        kept_motions.push_back(pm);
        continue;
      }
      // Rows over [point (3) | camera m (6) | successor (3) | motion (6)], residual last.
      Eigen::Matrix<double, 9, 19> A = Eigen::Matrix<double, 9, 19>::Zero();
      const Mat3 info = u->second.info + 1e-12 * Mat3::Identity();
      const Mat3 L = info.llt().matrixU();  // L^T L = info
      A.block<3, 3>(0, 0) = L;
      A.block<3, 1>(0, 18) = L.transpose().triangularView<Eigen::Lower>().solve(u->second.gradient);
      const PointVariable& point = graph->points.at(pm.prev_point_var);
      Mat3 J_point, J_prev, J_curr;
      Mat36 J_cam, J_motion;
      const PointMeasurementEntry& e = *meas->second;
      Vec3 r = PointMeasurementResidual(R, t, point.position(), e.z_camera, e.sigma_m.cwiseInverse(), &J_cam, &J_point);
      double w = huber.sqrtWeight(r.squaredNorm());
      A.block<3, 3>(3, 0) = w * J_point;
      A.block<3, 6>(3, 3) = w * J_cam;
      A.block<3, 1>(3, 18) = w * r;
      const MotionVariable& H = graph->motions.at(pm.motion_var);
      const Vec3 successor = graph->points.at(pm.curr_point_var).position();
      r = PointMotionResidual(BlockRotationMatrix(H.H_anchor.data()), BlockTranslation(H.H_anchor.data()), H.anchor_world,
                              point.position(), successor, Mat3::Identity() * inv_motion_sigma, &J_prev, &J_curr,
                              &J_motion);
      w = huber.sqrtWeight(r.squaredNorm());
      A.block<3, 3>(6, 0) = w * J_prev;
      A.block<3, 3>(6, 9) = w * J_curr;
      A.block<3, 6>(6, 12) = w * J_motion;
      A.block<3, 1>(6, 18) = w * r;
      // Eliminate the point: rotate its columns onto the first three rows; the other six rows no longer
      // involve it and are the marginal, exactly (no information is dropped here).
      const Eigen::HouseholderQR<Eigen::Matrix<double, 9, 3>> qr(A.leftCols<3>());
      const Eigen::Matrix<double, 9, 16> rotated = qr.householderQ().transpose() * A.rightCols<16>();
      LinearPointFactor lf;
      lf.camera_frame = m;
      lf.point_var = pm.curr_point_var;
      lf.motion_var = pm.motion_var;
      std::copy(cam, cam + kPoseBlockSize, lf.camera_lin.begin());
      lf.point_lin = successor;
      lf.motion_lin = H.H_anchor;
      lf.J = rotated.block<6, 15>(3, 0);
      lf.r0 = rotated.block<6, 1>(3, 15);
      next.linear_factors.push_back(lf);
    }
    next.point_motions.swap(kept_motions);
  }

  // Per-frame object points leave with their frame; points shared over frames (an object that was
  // static) stay until the camera window lets their measurements go.
  std::vector<PointMeasurementEntry> kept;
  kept.reserve(fm.measurements.size());
  for (const auto& e : fm.measurements) {
    const PointVariable& var = graph->points.at(e.point_var);
    if (selected(var.object_id) && var.first_frame == m && var.last_frame == m) {
      sink->pointFinal({m, var.track_id, var.object_id, var.position()});
      graph->points.erase(e.point_var);
    } else {
      kept.push_back(e);
    }
  }
  fm.measurements.swap(kept);
  // Transitions are in frame order; those of other objects stay until their own window lets them go.
  // A transition whose motion is its object's one motion for the whole track is final only when that
  // motion leaves (the track ended): until then every new frame still refines it.
  auto motion_stays = [&](int motion_var) {
    return motion_var >= 0 && graph->motions.at(motion_var).last_frame > m &&
           ObjectWindowOf(params, graph->motions.at(motion_var).object_id) == ObjectWindow::kTrackMotion;
  };
  std::deque<ObjectTransition> kept_transitions;
  for (ObjectTransition& tr : graph->transitions) {
    if (tr.frame > m || !selected(tr.object_id) || motion_stays(tr.motion_var)) {
      if (tr.centroid_prev_world) tr.prev_point_vars = {};  // those points are gone or going
      kept_transitions.push_back(std::move(tr));
      continue;
    }
    if (tr.reportable()) sink->motionFinal(MotionEstimateOf(*graph, tr, frame_rate_hz));
  }
  graph->transitions.swap(kept_transitions);
  if (m + 1 < graph->numFrames()) {
    for (auto& s : graph->frame(m + 1).smoothness) {
      if (s.prev_motion_var < 0 || graph->motions.at(s.prev_motion_var).last_frame > m ||
          !selected(graph->motions.at(s.prev_motion_var).object_id))
        continue;
      const MotionVariable& prev = graph->motions.at(s.prev_motion_var);
      s.prev_fixed = prev.H_anchor;
      s.prev_fixed_anchor = prev.anchor_world;
      s.prev_motion_var = -1;
    }
  }
  AccumulateLeavingSmoothness(params, m, graph);  // the motions into m are final: so are their smoothness residuals
  for (auto it = graph->motions.begin(); it != graph->motions.end();)
    it = it->second.last_frame <= m && selected(it->second.object_id) ? graph->motions.erase(it) : std::next(it);
  ForgetObjectsWithoutMotions(graph);
  // What frame m had into it from m-1 was folded into its points at m, which are gone now (those of
  // other objects stay with their points).
  if (which == ObjectWindow::kAll) {
    fm.point_motions.clear();
    fm.smoothness.clear();
    fm.linear_factors.clear();
  } else {
    auto gone_point = [&](int var) { return var >= 0 && !graph->points.count(var); };
    auto gone_motion = [&](int var) { return var >= 0 && !graph->motions.count(var); };
    EraseIf(fm.point_motions, [&](const PointMotionEntry& e) {
      return gone_point(e.prev_point_var) || gone_point(e.curr_point_var) || gone_motion(e.motion_var);
    });
    EraseIf(fm.linear_factors,
            [&](const LinearPointFactor& e) { return gone_point(e.point_var) || gone_motion(e.motion_var); });
    EraseIf(fm.smoothness,
            [&](const SmoothnessEntry& e) { return gone_motion(e.prev_motion_var) || gone_motion(e.curr_motion_var); });
  }
}

JacobianFactor PointPriorRows(int key, const PointVariable& var, const HuberLoss& huber) {
  GaussianMarginal normal;
  normal.keys = {key};
  normal.dims = {3};
  Mat3 info;
  Vec3 gradient;
  var.priorNormalEquations(var.position(), huber, &info, &gradient);
  normal.information = info;
  normal.gradient = gradient;
  return FactorOf(normal);
}

void MarginaliseCameraFrame(const BackendParams& params, int m, FactorGraph* graph, EstimateSink* sink) {
  const HuberLoss huber{params.noise.huber_delta};
  const double* cam = graph->camera(m);
  const Mat3 R = BlockRotationMatrix(cam);
  const Vec3 t = BlockTranslation(cam);
  FrameFactors& fm = graph->frame(m);
  // With camera_prior_by_schur, camera m is eliminated by a Schur complement with the landmarks only it
  // still measures, over its prior, the first-camera prior, its odometry to m+1 and those measurements:
  // what is left is the prior on camera m+1, which replaces the odometry into it.
  constexpr int kLeaving = -1, kNext = -2;  // landmark keys are their variable ids (>= 0)
  const bool chained =
      params.camera_prior_by_schur && m + 1 < graph->numFrames() && graph->frame(m + 1).odometry.has_value();
  std::vector<JacobianFactor> factors;
  std::vector<int> leaving = {kLeaving};
  if (chained) {
    if (graph->camera_prior && graph->camera_prior->frame == m)
      factors.push_back({{kLeaving}, {Eigen::MatrixXd(graph->camera_prior->R)}, graph->camera_prior->residual(cam)});
    Mat6 J_prev, J_next;
    if (m == 0) {
      const std::unique_ptr<ceres::CostFunction> prior(PosePriorFactor::Create(graph->T_world_camera0_prior, graph->prior_sigma));
      Mat6* J[1] = {&J_prev};
      const Vec6 r = LinearisePoseFactor(*prior, &cam, J);
      factors.push_back({{kLeaving}, {Eigen::MatrixXd(J_prev)}, r});
    }
    const OdometryEntry& odometry = *graph->frame(m + 1).odometry;
    const std::unique_ptr<ceres::CostFunction> factor(OdometryFactor::Create(odometry.T_prev_curr, odometry.sigma));
    const double* blocks[2] = {cam, graph->camera(m + 1)};
    Mat6* J[2] = {&J_prev, &J_next};
    const Vec6 r = LinearisePoseFactor(*factor, blocks, J);
    factors.push_back({{kLeaving, kNext}, {Eigen::MatrixXd(J_prev), Eigen::MatrixXd(J_next)}, r});
  }
  std::unordered_set<int> ended;
  for (const auto& e : fm.measurements) {
    PointVariable& var = graph->points.at(e.point_var);
    sink->pointFinal({m, var.track_id, var.object_id, var.position()});
    if (var.last_frame <= m) {
      // A landmark seen last from here leaves with the camera: its history reaches camera m+1 through it.
      const bool with_camera = chained && var.object_id < 0;
      if (ended.insert(e.point_var).second && with_camera) {
        leaving.push_back(e.point_var);
        if (var.hasPrior()) factors.push_back(PointPriorRows(e.point_var, var, huber));
      }
      if (with_camera) {
        Mat36 J_cam;
        Mat3 J_point;
        const Vec3 r = PointMeasurementResidual(R, t, var.position(), e.z_camera, e.sigma_m.cwiseInverse(), &J_cam, &J_point);
        const double w = huber.sqrtWeight(r.squaredNorm());
        factors.push_back({{kLeaving, e.point_var}, {Eigen::MatrixXd(w * J_cam), Eigen::MatrixXd(w * J_point)}, w * r});
      }
      continue;
    }
    // A landmark still measured in the window keeps this measurement with the camera held at its final
    // estimate (the sparsification: the prior would otherwise couple every such landmark with camera
    // m+1 and each other). It is held as a robust factor for landmark_history_frames frames, then folded
    // into the landmark's prior. With the camera held the measurement is linear in the point,
    // r = W (R^T (l - t) - z) = W R^T (l - (t + R z)), so the fold is exact but for the Huber weight,
    // frozen when it folds.
    var.held.push_back({e.sigma_m.cwiseInverse().asDiagonal() * R.transpose(), t + R * e.z_camera, m});
    while (static_cast<int>(var.held.size()) > params.landmark_history_frames) var.foldOldestHeld(var.position(), huber);
  }
  graph->camera_prior.reset();
  if (chained) {
    try {
      const SquareRootRows rows = SquareRootOf(MarginaliseBySchur(factors, leaving));
      CameraPrior prior;
      prior.frame = m + 1;
      std::copy(graph->camera(m + 1), graph->camera(m + 1) + kPoseBlockSize, prior.camera_lin.begin());
      prior.R.topRows(rows.R.rows()) = rows.R;
      prior.r0.head(rows.r.size()) = rows.r;
      graph->camera_prior = prior;
      graph->frame(m + 1).odometry.reset();
    } catch (const std::runtime_error&) {
      // Not determined (cannot happen with an odometry factor of finite sigma): camera m stays held as
      // the next window's anchor through its odometry factor, as a smoother without the prior would.
    }
  }
  for (int v : ended) graph->points.erase(v);
  // Linear factors on this camera (left by object points of frame m) keep it at its final value.
  if (m + 1 < graph->numFrames())
    for (auto& lf : graph->frame(m + 1).linear_factors) {
      if (lf.camera_frame != m) continue;
      lf.r0 += lf.J.leftCols<6>() * PoseBlockMinus(cam, lf.camera_lin.data());
      lf.J.leftCols<6>().setZero();
      lf.camera_frame = -1;
    }
  fm = FrameFactors{fm.odometry, {}, {}, {}, {}};
  sink->cameraFinal(m, BlockToPose(cam));
  graph->retireFramesBefore(m);
}

}  // namespace dslam
