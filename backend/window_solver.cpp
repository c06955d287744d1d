#include "backend/window_solver.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <vector>

#include "backend/factors/analytic_jacobians.h"
#include "backend/factors/huber_loss.h"
#include "backend/factors/motion_smoothness_factor.h"
#include "backend/factors/odometry_factor.h"
#include "backend/factors/pose_factor_linearisation.h"
#include "backend/factors/pose_prior_factor.h"
#include "backend/process_noise.h"
#include "backend/spd_inverse.h"

namespace dslam {
namespace {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;


struct Measurement {
  int pose;  // pose-block index, -1: camera held constant
  int point;
  const double* camera;
  Vec3 z;
  Vec3 inv_sigma;
};

struct PointMotion {
  int prev;  // point index
  int curr;
  int motion;  // pose-block index
  Vec3 anchor;
};

// A linear factor left by a marginalised object point (backend/factor_graph.h).
struct Linear {
  int camera;  // pose-block index; -1: held (camera_value) or folded (camera_value null)
  const double* camera_value;
  int point;
  int motion;  // pose-block index
  const LinearPointFactor* factor;
};

// Odometry, first-camera prior and smoothness: few and 6-dimensional. Their one definition is the
// templated functor in backend/factors/ that Ceres' batch solver uses; its autodiff Jacobian in the
// block's seven coordinates, times the manifold's Plus Jacobian, is the Jacobian in the tangent.
struct PoseFactor {
  int a = -1, b = -1;  // pose-block indices; -1: the constant block below (or absent for a unary factor)
  const double* a_fixed = nullptr;
  std::shared_ptr<const ceres::CostFunction> cost;  // residual 6; parameter blocks: a, or a and b
  const HuberLoss* robust = nullptr;                // none: plain least squares
};

struct Group {
  std::vector<int> points;
  std::vector<int> measurements;
  std::vector<int> motions;
  std::vector<int> linears;
  // Elimination results of the current linearisation: dp = -(y + Y dx_local).
  std::vector<int> poses;  // local pose index -> pose-block index
  MatX Y;
  VecX y;
};

class WindowProblem {
 public:
  WindowProblem(const BackendParams& params, const WindowSolveOptions& options, FactorGraph* graph)
      : params_(params), huber_{params.noise.huber_delta}, motion_whitening_(Mat3::Identity() / params.noise.motion_sigma_m) {
    if (params.noise.smoothness_huber_delta > 0.0) smoothness_huber_ = HuberLoss{params.noise.smoothness_huber_delta};
    const int first = options.first_frame, last = options.last_frame;
    auto point_index = [&](int id) {
      auto [it, is_new] = point_index_.try_emplace(id, static_cast<int>(points_.size()));
      if (is_new) points_.push_back(&graph->points.at(id));
      return it->second;
    };
    if (!options.fix_cameras)
      for (int k = first; k <= last; ++k) poses_.push_back(graph->camera(k));
    const int num_cameras = num_cameras_ = static_cast<int>(poses_.size());
    auto camera_index = [&](int k) { return options.fix_cameras || k < first ? -1 : k - first; };
    auto motion_index = [&](int id) {
      auto [it, is_new] = motion_index_.try_emplace(id, static_cast<int>(poses_.size()));
      if (is_new) {
        poses_.push_back(graph->motions.at(id).H_anchor.data());
        motion_anchor_.push_back(graph->motions.at(id).anchor_world);
      }
      return it->second;
    };

    // What the cameras that left the window said about its first camera (their odometry into it was
    // eliminated with them).
    if (!options.fix_cameras && graph->camera_prior && graph->camera_prior->frame == first && num_cameras > 0)
      camera_prior_ = &*graph->camera_prior;
    if (first == 0 && !options.fix_cameras) {
      pose_factors_.push_back({0, -1, nullptr, Shared(PosePriorFactor::Create(graph->T_world_camera0_prior, graph->prior_sigma))});
    }
    for (int k = first; k <= last; ++k) {
      const FrameFactors& f = graph->frame(k);
      if (f.odometry && k > 0 && !options.fix_cameras) {
        pose_factors_.push_back({camera_index(k - 1), camera_index(k), graph->camera(k - 1),
                                 Shared(OdometryFactor::Create(f.odometry->T_prev_curr, f.odometry->sigma))});
      }
      for (const auto& m : f.measurements)
        measurements_.push_back({camera_index(k), point_index(m.point_var), graph->camera(k), m.z_camera,
                                 m.sigma_m.cwiseInverse()});
      for (const auto& m : f.point_motions) {
        const int h = motion_index(m.motion_var);
        PointMotion pm{point_index(m.prev_point_var), point_index(m.curr_point_var), h, motion_anchor_[h - num_cameras]};
        motions_.push_back(pm);
      }
      for (const auto& lf : f.linear_factors) {
        const bool has_camera = lf.camera_frame >= 0;
        linears_.push_back({has_camera ? camera_index(lf.camera_frame) : -1,
                            has_camera ? graph->camera(lf.camera_frame) : nullptr, point_index(lf.point_var),
                            motion_index(lf.motion_var), &lf});
      }
      for (const auto& s : f.smoothness) {
        const int b = motion_index(s.curr_motion_var);
        const bool prev_live = s.prev_motion_var >= 0;
        const int a = prev_live ? motion_index(s.prev_motion_var) : -1;
        const Vec3 anchor_prev = prev_live ? motion_anchor_[a - num_cameras] : s.prev_fixed_anchor;
        pose_factors_.push_back({a, b, prev_live ? nullptr : s.prev_fixed.data(),
                                 Shared(MotionSmoothnessFactor::Create(
                                     SmoothnessSigma(params, *graph, graph->motions.at(s.curr_motion_var).object_id),
                                     anchor_prev, motion_anchor_[b - num_cameras])),
                                 smoothness_huber_ ? &*smoothness_huber_ : nullptr});
      }
    }
    buildGroups();
  }

  int numResidualBlocks() const {
    int n = static_cast<int>(measurements_.size() + motions_.size() + linears_.size() + pose_factors_.size()) +
            (camera_prior_ ? 1 : 0);
    for (const PointVariable* p : points_) n += p->hasPrior() ? 1 : 0;
    return n;
  }
  bool empty() const { return poses_.empty() && points_.empty(); }

  double cost() const {
    double c = 0.0;
    for (const auto& m : measurements_) {
      const double* cam = m.pose >= 0 ? poses_[m.pose] : m.camera;
      const Vec3 r = PointMeasurementResidual(BlockRotationMatrix(cam), BlockTranslation(cam), point(m.point), m.z, m.inv_sigma,
                                              nullptr, nullptr);
      c += huber_.rho(r.squaredNorm());
    }
    for (const auto& m : motions_) {
      const double* H = poses_[m.motion];
      const Vec3 r = PointMotionResidual(BlockRotationMatrix(H), BlockTranslation(H), m.anchor, point(m.prev), point(m.curr), motion_whitening_,
                                         nullptr, nullptr, nullptr);
      c += huber_.rho(r.squaredNorm());
    }
    for (const auto& l : linears_) c += linearResidual(l).squaredNorm();
    for (const auto& f : pose_factors_) {
      const double s = poseResidual(f, nullptr).squaredNorm();
      c += f.robust ? f.robust->rho(s) : s;
    }
    if (camera_prior_) c += camera_prior_->residual(poses_[0]).squaredNorm();
    c *= 0.5;
    for (const PointVariable* p : points_)
      if (p->hasPrior()) c += p->priorCost(p->position(), huber_);
    return c;
  }

  // Builds and solves the damped normal equations; false when the reduced system is not positive definite.
  bool computeStep(double lambda, VecX* dx, std::vector<Vec3>* dp) {
    MatX S;
    VecX b;
    if (!buildReduced(lambda, &S, &b)) return false;
    ReducedSystem reduced(6 * num_cameras_);
    last_reduced_.reset();
    if (!reduced.factorise(S)) return false;
    *dx = reduced.solve(-b);
    last_reduced_ = std::move(reduced);
    last_lambda_ = lambda;
    dp->assign(points_.size(), Vec3::Zero());
    for (const Group& g : groups_) {
      VecX dx_local(6 * g.poses.size());
      for (size_t j = 0; j < g.poses.size(); ++j) dx_local.segment<6>(6 * j) = dx->segment<6>(6 * g.poses[j]);
      const VecX d = -(g.y + g.Y * dx_local);
      for (size_t i = 0; i < g.points.size(); ++i) (*dp)[g.points[i]] = d.segment<3>(3 * i);
    }
    return dx->allFinite();
  }

  // The marginal covariance of each motion of the window (the points, the cameras and the other motions
  // marginalised out), by motion-variable id, from the system of the last step: linearised one step
  // before the estimate and damped by the last (small, at convergence) LM lambda, which linearising
  // again at the estimate would change by less than the covariance's own accuracy, at the cost of one
  // more iteration. Empty when there was no step or its system was not positive definite.
  std::unordered_map<int, Mat6> motionCovariances() const {
    std::unordered_map<int, Mat6> out;
    if (!last_reduced_) return out;
    const std::vector<Mat6> blocks = last_reduced_->motionCovariances();
    for (const auto& [id, index] : motion_index_) out[id] = blocks[index - num_cameras_];
    return out;
  }

  double lastDamping() const { return last_reduced_ ? last_lambda_ : 0.0; }

  // Each consecutive camera pair's step covariance from the same system: J Sigma_pair J^T, J the step's
  // Jacobian in both cameras' tangents. Empty when there was no step or fewer than two cameras.
  std::vector<CameraStepCovariance> cameraStepCovariances(int first_frame) const {
    std::vector<CameraStepCovariance> out;
    if (!last_reduced_ || num_cameras_ < 2) return out;
    const MatX covariance = last_reduced_->cameraCovariance();
    for (int i = 1; i < num_cameras_; ++i) {
      const Mat3 R_a = BlockRotationMatrix(poses_[i - 1]), R_b = BlockRotationMatrix(poses_[i]);
      const Vec3 t_step = R_a.transpose() * (BlockTranslation(poses_[i]) - BlockTranslation(poses_[i - 1]));
      // t_step = R_a^T (t_b - t_a), R_step = R_a^T R_b; (R, t) <- (R Exp(phi), t + dt) in each camera.
      Eigen::Matrix<double, 6, 12> J = Eigen::Matrix<double, 6, 12>::Zero();
      J.block<3, 3>(0, 0) = -R_a.transpose();
      J.block<3, 3>(0, 3) = Hat(t_step);
      J.block<3, 3>(0, 6) = R_a.transpose();
      J.block<3, 3>(3, 3) = -(R_a.transpose() * R_b).transpose();
      J.block<3, 3>(3, 9) = Mat3::Identity();
      out.push_back({first_frame + i, J * covariance.block<12, 12>(6 * (i - 1), 6 * (i - 1)) * J.transpose()});
    }
    return out;
  }

 private:
  // The normal equations with every point group eliminated: S over the cameras then the motions. False
  // when a group's own block is not positive definite. Contributions go to the blocks on and above the
  // diagonal only (a 6x6 block at block row <= block column), mirrored once at the end: half the
  // scattered writes.
  bool buildReduced(double lambda, MatX* S, VecX* b) {
    const int n = 6 * static_cast<int>(poses_.size());
    *S = MatX::Zero(n, n);
    *b = VecX::Zero(n);
    VecX diag = VecX::Zero(n);  // undamped diagonal of the pose-pose block, for the damping
    for (Group& g : groups_)
      if (!eliminate(g, lambda, S, b, &diag)) return false;
    for (const auto& f : pose_factors_) addPoseFactor(f, S, b, &diag);
    if (camera_prior_) {
      // Its Jacobian stays the one it was made with (first-estimate Jacobian), so that the information it
      // carries is not changed by the steps of the cameras it was made from.
      const Mat6& R = camera_prior_->R;
      S->topLeftCorner<6, 6>() += R.transpose() * R;
      b->head<6>() += R.transpose() * camera_prior_->residual(poses_[0]);
      diag.head<6>() += R.colwise().squaredNorm().transpose();
    }
    for (int j = 0; j < n; ++j)
      for (int i = j + 1; i < n; ++i) (*S)(i, j) = (*S)(j, i);
    for (int i = 0; i < n; ++i) (*S)(i, i) += lambda * std::max(diag[i], 1e-9) + 1e-12;
    return true;
  }

  // The reduced system S factorised by its structure. The motions of different objects are not coupled
  // (cameras couple everything), so each object's motions (a component) are eliminated first, block by
  // block, into the camera system, which is then factorised densely: a few small factorisations and one
  // 6W x 6W, instead of one over every motion.
  class ReducedSystem {
   public:
    explicit ReducedSystem(int camera_rows) : nc_(camera_rows) {}

    bool factorise(const MatX& S) {
      const int num_motions = (static_cast<int>(S.rows()) - nc_) / 6;
      std::vector<int> parent(num_motions);
      std::iota(parent.begin(), parent.end(), 0);
      std::function<int(int)> find = [&](int i) { return parent[i] == i ? i : parent[i] = find(parent[i]); };
      for (int i = 0; i < num_motions; ++i)
        for (int j = i + 1; j < num_motions; ++j)
          if (!S.block<6, 6>(nc_ + 6 * i, nc_ + 6 * j).isZero(0.0)) parent[find(i)] = find(j);
      std::vector<std::vector<int>> rows_of(num_motions);
      for (int i = 0; i < num_motions; ++i)
        for (int r = 0; r < 6; ++r) rows_of[find(i)].push_back(nc_ + 6 * i + r);
      std::vector<int> camera_rows(nc_);
      std::iota(camera_rows.begin(), camera_rows.end(), 0);
      MatX Scc = S.topLeftCorner(nc_, nc_);
      for (std::vector<int>& rows : rows_of) {
        if (rows.empty()) continue;
        Component c{std::move(rows), Eigen::LLT<MatX>(), MatX()};
        c.llt.compute(S(c.rows, c.rows));
        if (c.llt.info() != Eigen::Success) return false;
        c.Ainv_Bt = c.llt.solve(MatX(S(camera_rows, c.rows).transpose()));
        Scc.noalias() -= S(camera_rows, c.rows) * c.Ainv_Bt;
        components_.push_back(std::move(c));
      }
      if (nc_ > 0) {
        cameras_.compute(Scc);
        if (cameras_.info() != Eigen::Success) return false;
      }
      size_ = S.rows();
      return true;
    }

    // S x = rhs.
    VecX solve(const VecX& rhs) const {
      VecX x(size_);
      VecX rc = rhs.head(nc_);
      std::vector<VecX> Ainv_r;
      for (const Component& c : components_) {
        const VecX r = rhs(c.rows);
        Ainv_r.push_back(c.llt.solve(r));
        rc.noalias() -= c.Ainv_Bt.transpose() * r;
      }
      if (nc_ > 0) x.head(nc_) = cameras_.solve(rc);
      for (size_t i = 0; i < components_.size(); ++i) {
        const Component& c = components_[i];
        const VecX xm = Ainv_r[i] - c.Ainv_Bt * x.head(nc_);
        for (size_t r = 0; r < c.rows.size(); ++r) x[c.rows[r]] = xm[static_cast<Eigen::Index>(r)];
      }
      return x;
    }

    // The cameras' block of S^-1: the inverse of their Schur complement (empty without cameras).
    MatX cameraCovariance() const {
      return nc_ > 0 ? MatX(cameras_.solve(MatX::Identity(nc_, nc_))) : MatX();
    }

    // The 6x6 diagonal blocks of S^-1 for the motions, in motion order:
    // A^-1 + (A^-1 B^T) Scc'^-1 (B A^-1) per component, Scc' the cameras' Schur complement.
    std::vector<Mat6> motionCovariances() const {
      std::vector<Mat6> out((size_ - nc_) / 6, Mat6::Zero());
      for (const Component& c : components_) {
        MatX cov = c.llt.solve(MatX::Identity(c.rows.size(), c.rows.size()));
        if (nc_ > 0) {
          const MatX L_inv_E = cameras_.matrixL().solve(MatX(c.Ainv_Bt.transpose()));
          cov.noalias() += L_inv_E.transpose() * L_inv_E;
        }
        for (size_t r = 0; r < c.rows.size(); r += 6)
          out[(c.rows[r] - nc_) / 6] = cov.block<6, 6>(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(r));
      }
      return out;
    }

   private:
    struct Component {
      std::vector<int> rows;  // of S
      Eigen::LLT<MatX> llt;   // of its block A
      MatX Ainv_Bt;           // A^-1 B^T, B its coupling to the cameras
    };
    int nc_;
    Eigen::Index size_ = 0;
    std::vector<Component> components_;
    Eigen::LLT<MatX> cameras_;
  };

 public:
  // Applies a step; the previous values are kept for undo().
  void apply(const VecX& dx, const std::vector<Vec3>& dp) {
    saved_poses_.resize(poses_.size());
    saved_points_.resize(points_.size());
    for (size_t i = 0; i < poses_.size(); ++i) {
      std::copy(poses_[i], poses_[i] + kPoseBlockSize, saved_poses_[i].begin());
      PoseBlockPlus(saved_poses_[i].data(), dx.segment<6>(6 * i), poses_[i]);
    }
    for (size_t i = 0; i < points_.size(); ++i) {
      saved_points_[i] = points_[i]->p_world;
      for (int a = 0; a < 3; ++a) points_[i]->p_world[a] += dp[i][a];
    }
  }
  void undo() {
    for (size_t i = 0; i < poses_.size(); ++i) std::copy(saved_poses_[i].begin(), saved_poses_[i].end(), poses_[i]);
    for (size_t i = 0; i < points_.size(); ++i) points_[i]->p_world = saved_points_[i];
  }

 private:
  Vec3 point(int i) const { return points_[i]->position(); }

  Vec6 linearResidual(const Linear& l) const {
    return l.factor->residual(l.camera >= 0 ? poses_[l.camera] : l.camera_value, point(l.point), poses_[l.motion]);
  }

  // Point groups: connected components of the point-motion factors between two point variables.
  void buildGroups() {
    std::vector<int> parent(points_.size());
    std::iota(parent.begin(), parent.end(), 0);
    std::function<int(int)> find = [&](int i) { return parent[i] == i ? i : parent[i] = find(parent[i]); };
    for (const auto& m : motions_)
      parent[find(m.prev)] = find(m.curr);
    std::vector<int> group_of(points_.size(), -1);
    for (size_t i = 0; i < points_.size(); ++i) {
      const int root = find(static_cast<int>(i));
      if (group_of[root] < 0) {
        group_of[root] = static_cast<int>(groups_.size());
        groups_.emplace_back();
      }
      group_of[i] = group_of[root];
      groups_[group_of[i]].points.push_back(static_cast<int>(i));
    }
    local_index_.assign(points_.size(), 0);
    for (const Group& g : groups_)
      for (size_t j = 0; j < g.points.size(); ++j) local_index_[g.points[j]] = static_cast<int>(j);
    for (size_t i = 0; i < measurements_.size(); ++i) groups_[group_of[measurements_[i].point]].measurements.push_back(i);
    for (size_t i = 0; i < motions_.size(); ++i) groups_[group_of[motions_[i].curr]].motions.push_back(i);
    for (size_t i = 0; i < linears_.size(); ++i) groups_[group_of[linears_[i].point]].linears.push_back(i);
    for (Group& g : groups_) {
      for (int i : g.measurements)
        if (measurements_[i].pose >= 0) g.poses.push_back(measurements_[i].pose);
      for (int i : g.motions) g.poses.push_back(motions_[i].motion);
      for (int i : g.linears) {
        if (linears_[i].camera >= 0) g.poses.push_back(linears_[i].camera);
        g.poses.push_back(linears_[i].motion);
      }
      std::sort(g.poses.begin(), g.poses.end());
      g.poses.erase(std::unique(g.poses.begin(), g.poses.end()), g.poses.end());
    }
  }

  // Linearises one point group and adds its Schur complement to the reduced pose system. Groups are
  // small (a landmark: 3 unknowns; an object point's chain: 3 per frame of the object window), so their
  // blocks have fixed sizes up to four points; longer chains take heap matrices.
  bool eliminate(Group& g, double lambda, MatX* S, VecX* b, VecX* diag) {
    switch (g.points.size()) {
      case 1: return eliminateWith<3>(g, lambda, S, b, diag);
      case 2: return eliminateWith<6>(g, lambda, S, b, diag);
      case 3: return eliminateWith<9>(g, lambda, S, b, diag);
      case 4: return eliminateWith<12>(g, lambda, S, b, diag);
      default: return eliminateWith<Eigen::Dynamic>(g, lambda, S, b, diag);
    }
  }

  // A group's factors touch one pose each, except the linear factors (a camera and a motion): their
  // pose-pose terms go straight into S. The point-pose coupling W_a is kept as sparse 3x6 row blocks and
  // its Schur complement -W_a^T Hpp^-1 W_c is formed block by block.
  template <int kNp>
  bool eliminateWith(Group& g, double lambda, MatX* S, VecX* b, VecX* diag) {
    using MatPP = Eigen::Matrix<double, kNp, kNp>;
    using VecP = Eigen::Matrix<double, kNp, 1>;
    const int np = 3 * static_cast<int>(g.points.size()), num_poses = static_cast<int>(g.poses.size());
    auto local_pose = [&](int pose) {
      return static_cast<int>(std::lower_bound(g.poses.begin(), g.poses.end(), pose) - g.poses.begin());
    };
    MatPP Hpp = MatPP::Zero(np, np);
    VecP gp = VecP::Zero(np);
    // The point-pose coupling is sparse: a pose touches one or two of the group's points (a camera its
    // point, a motion the two ends of its factor), so W_a is kept as its nonzero 3x6 row blocks.
    std::vector<WBlock>& W = scratch_blocks_;
    W.clear();
    auto add_w = [&](int pose, int row, const Mat36& block) {
      const int a = local_pose(pose);
      for (WBlock& w : W)
        if (w.pose == a && w.row == row) {
          w.B += block;
          return;
        }
      W.push_back({a, row, block});
    };
    auto add_pose = [&](int pose, const Mat36& Jpose, const Vec3& r) {
      S->block<6, 6>(6 * pose, 6 * pose) += Jpose.transpose() * Jpose;
      b->segment<6>(6 * pose) += Jpose.transpose() * r;
      diag->segment<6>(6 * pose) += Jpose.colwise().squaredNorm().transpose();
    };
    Mat36 Jpose;
    Mat3 Jl, Jprev, Jcurr;
    for (int mi : g.measurements) {
      const Measurement& m = measurements_[mi];
      const double* cam = m.pose >= 0 ? poses_[m.pose] : m.camera;
      Vec3 r = PointMeasurementResidual(BlockRotationMatrix(cam), BlockTranslation(cam), point(m.point), m.z, m.inv_sigma,
                                        m.pose >= 0 ? &Jpose : nullptr, &Jl);
      const double w = huber_.sqrtWeight(r.squaredNorm());
      r *= w, Jl *= w, Jpose *= w;
      const int i = 3 * local_index_[m.point];
      Hpp.template block<3, 3>(i, i) += Jl.transpose() * Jl;
      gp.template segment<3>(i) += Jl.transpose() * r;
      if (m.pose >= 0) {
        add_w(m.pose, i, Jl.transpose() * Jpose);
        add_pose(m.pose, Jpose, r);
      }
    }
    for (int mi : g.motions) {
      const PointMotion& m = motions_[mi];
      const double* H = poses_[m.motion];
      Vec3 r = PointMotionResidual(BlockRotationMatrix(H), BlockTranslation(H), m.anchor, point(m.prev), point(m.curr), motion_whitening_, &Jprev,
                                   &Jcurr, &Jpose);
      const double w = huber_.sqrtWeight(r.squaredNorm());
      r *= w, Jprev *= w, Jcurr *= w, Jpose *= w;
      const int j = 3 * local_index_[m.curr];
      Hpp.template block<3, 3>(j, j) += Jcurr.transpose() * Jcurr;
      gp.template segment<3>(j) += Jcurr.transpose() * r;
      add_w(m.motion, j, Jcurr.transpose() * Jpose);
      const int i = 3 * local_index_[m.prev];
      Hpp.template block<3, 3>(i, i) += Jprev.transpose() * Jprev;
      Hpp.template block<3, 3>(i, j) += Jprev.transpose() * Jcurr;
      Hpp.template block<3, 3>(j, i) += Jcurr.transpose() * Jprev;
      gp.template segment<3>(i) += Jprev.transpose() * r;
      add_w(m.motion, i, Jprev.transpose() * Jpose);
      add_pose(m.motion, Jpose, r);
    }
    for (int li : g.linears) {
      // Plain squares (weighted when linearised); it couples its camera and motion directly.
      const Linear& l = linears_[li];
      const Vec6 r = linearResidual(l);
      const Eigen::Matrix<double, 6, 15>& J = l.factor->J;
      const int j = 3 * local_index_[l.point];
      const Eigen::Matrix<double, 6, 3> Jp = J.middleCols<3>(6);
      Hpp.template block<3, 3>(j, j) += Jp.transpose() * Jp;
      gp.template segment<3>(j) += Jp.transpose() * r;
      const int blocks[2] = {l.camera, l.motion};
      for (int a = 0; a < 2; ++a) {
        if (blocks[a] < 0) continue;
        const Mat6 Ja = a == 0 ? Mat6(J.leftCols<6>()) : Mat6(J.rightCols<6>());
        add_w(blocks[a], j, Jp.transpose() * Ja);
        b->segment<6>(6 * blocks[a]) += Ja.transpose() * r;
        diag->segment<6>(6 * blocks[a]) += Ja.colwise().squaredNorm().transpose();
        for (int c = 0; c < 2; ++c) {
          if (blocks[c] < blocks[a]) continue;  // upper blocks only (blocks[a] >= 0 here)
          const Mat6 Jc = c == 0 ? Mat6(J.leftCols<6>()) : Mat6(J.rightCols<6>());
          S->block<6, 6>(6 * blocks[a], 6 * blocks[c]) += Ja.transpose() * Jc;
        }
      }
    }
    for (size_t j = 0; j < g.points.size(); ++j) {
      const PointVariable* p = points_[g.points[j]];
      if (!p->hasPrior()) continue;
      const int i = 3 * static_cast<int>(j);
      Mat3 info;
      Vec3 gradient;
      p->priorNormalEquations(point(g.points[j]), huber_, &info, &gradient);
      Hpp.template block<3, 3>(i, i) += info;
      gp.template segment<3>(i) += gradient;
    }
    for (int i = 0; i < np; ++i) Hpp(i, i) += lambda * Hpp(i, i) + 1e-12;
    // Through the explicit inverse and coefficient-wise (lazy) fixed-size products: solving into blocks of
    // the dynamic Y, or Eigen's blocked GEMM above 20 summed dimensions, took most of the solve time.
    MatPP Hpp_inv;
    if (!InverseSpd<kNp>(Hpp, &Hpp_inv)) return false;
    const VecP y = Hpp_inv * gp;
    g.y = y;
    // Y_c = Hpp^-1 W_c, summed over W_c's row blocks, straight into the group's Y; the Schur blocks
    // W_a^T Y_c likewise. Y's column blocks are contiguous (column-major), so each is mapped at its fixed
    // size: products with a block of the dynamic matrix itself were not unrolled.
    g.Y.setZero(np, 6 * num_poses);
    auto Y = [&](int a) { return Eigen::Map<Eigen::Matrix<double, kNp, 6>>(g.Y.data() + 6 * a * np, np, 6); };
    for (const WBlock& w : W) Y(w.pose).noalias() += Hpp_inv.template middleCols<3>(w.row).lazyProduct(w.B);
    for (const WBlock& w : W) {
      const int pa = g.poses[w.pose];
      b->segment<6>(6 * pa).noalias() -= w.B.transpose() * y.template segment<3>(w.row);
      // g.poses is sorted, so c >= w.pose is a block on or above the diagonal.
      for (int c = w.pose; c < num_poses; ++c) {
        const Mat6 block = w.B.transpose().lazyProduct(Y(c).template middleRows<3>(w.row));
        S->block<6, 6>(6 * pa, 6 * g.poses[c]) -= block;
      }
    }
    return true;
  }

  // Residual of a pose factor at the current values, and (J non-null) its Jacobians in the tangents of
  // its live blocks (J[0] of a, J[1] of b).
  Vec6 poseResidual(const PoseFactor& f, Mat6* J) const {
    const double* blocks[2] = {f.a >= 0 ? poses_[f.a] : f.a_fixed, f.b >= 0 ? poses_[f.b] : nullptr};
    Mat6* wanted[2] = {J && f.a >= 0 ? &J[0] : nullptr, J && f.b >= 0 ? &J[1] : nullptr};
    return LinearisePoseFactor(*f.cost, blocks, wanted);
  }

  void addPoseFactor(const PoseFactor& f, MatX* S, VecX* b, VecX* diag) const {
    const int blocks[2] = {f.a, f.b};
    Mat6 J[2];
    Vec6 r = poseResidual(f, J);
    if (f.robust) {  // iteratively reweighted, as the measurements
      const double w = f.robust->sqrtWeight(r.squaredNorm());
      r *= w, J[0] *= w, J[1] *= w;
    }
    for (int i = 0; i < 2; ++i) {
      if (blocks[i] < 0) continue;
      b->segment<6>(6 * blocks[i]) += J[i].transpose() * r;
      for (int j = 0; j < 2; ++j)
        if (blocks[j] >= blocks[i]) S->block<6, 6>(6 * blocks[i], 6 * blocks[j]) += J[i].transpose() * J[j];
      diag->segment<6>(6 * blocks[i]) += J[i].colwise().squaredNorm().transpose();
    }
  }

  static std::shared_ptr<const ceres::CostFunction> Shared(ceres::CostFunction* cost) {
    return std::shared_ptr<const ceres::CostFunction>(cost);
  }

  const BackendParams& params_;
  HuberLoss huber_;
  std::optional<HuberLoss> smoothness_huber_;
  Mat3 motion_whitening_;  // of the ternary factor: 1 / motion_sigma
  std::vector<double*> poses_;  // cameras first, then motions
  int num_cameras_ = 0;
  std::vector<Vec3> motion_anchor_;
  std::unordered_map<int, int> motion_index_, point_index_;
  std::vector<PointVariable*> points_;
  std::vector<Measurement> measurements_;
  std::vector<PointMotion> motions_;
  std::vector<Linear> linears_;
  std::vector<PoseFactor> pose_factors_;
  const CameraPrior* camera_prior_ = nullptr;  // on pose block 0, the window's first camera
  std::vector<Group> groups_;
  std::vector<int> local_index_;
  struct WBlock {
    int pose;  // local
    int row;   // first of the point's three rows
    Mat36 B;
  };
  std::vector<WBlock> scratch_blocks_;
  std::optional<ReducedSystem> last_reduced_;  // of the last computeStep, for the covariances
  double last_lambda_ = 0.0;                   // its damping
  std::vector<PoseBlock> saved_poses_;
  std::vector<std::array<double, 3>> saved_points_;
};

// Each motion's marginal covariance from the problem's last step into the graph.
void StoreMotionCovariances(const WindowProblem& problem, FactorGraph* graph) {
  for (const auto& [id, covariance] : problem.motionCovariances()) graph->motions.at(id).covariance = covariance;
}

}  // namespace

WindowSolveSummary SolveWindow(const BackendParams& params, const WindowSolveOptions& options, FactorGraph* graph) {
  WindowSolveSummary summary;
  if (options.last_frame < options.first_frame) return summary;
  WindowProblem problem(params, options, graph);
  summary.num_residual_blocks = problem.numResidualBlocks();
  if (problem.empty() || summary.num_residual_blocks == 0) return summary;

  double cost = problem.cost();
  summary.initial_cost = summary.final_cost = cost;
  if (options.covariance_only) {
    Eigen::VectorXd dx;
    std::vector<Vec3> dp;
    // A whisper of damping: on a batch graph the motions at the window's first frame have lost the
    // information of their points' previous frame, and those of an object leaving there have none.
    if (problem.computeStep(1e-9, &dx, &dp)) {
      StoreMotionCovariances(problem, graph);
      if (options.camera_step_covariance) summary.camera_step_covariances = problem.cameraStepCovariances(options.first_frame);
    }
    return summary;
  }
  double lambda = 1e-4;  // as Ceres' default initial trust region (radius 1e4)
  Eigen::VectorXd dx;
  std::vector<Vec3> dp;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    ++summary.num_iterations;
    if (!problem.computeStep(lambda, &dx, &dp)) {
      lambda *= 10.0;
      continue;
    }
    problem.apply(dx, dp);
    const double new_cost = problem.cost();
    if (!(new_cost < cost)) {
      problem.undo();
      lambda *= 10.0;
      if (lambda > 1e8) break;
      continue;
    }
    const double decrease = (cost - new_cost) / std::max(cost, 1e-300);
    std::vector<double>& decreases = summary.relative_decreases;
    decreases.push_back(decrease);
    cost = new_cost;
    lambda = std::max(lambda / 3.0, 1e-10);
    if (decrease < options.function_tolerance) break;
    // The next decrease, predicted from the last two, would be below the tolerance too: that step would not
    // be worth its linearisation (on the demo scene, 75 of the 244 iterations of its 60 solves).
    if (decreases.size() >= 2 && decrease * (decrease / decreases[decreases.size() - 2]) < options.function_tolerance)
      break;
  }
  summary.final_cost = cost;
  // The covariances read the last factorisation. One damped far more than a converged step's (the loop
  // ended on rejected steps, or the start was already the optimum) would understate them: factorise
  // again with a whisper of damping.
  constexpr double kMaxCovarianceDamping = 1e-3;  // understates a covariance by at most 0.1 %
  if ((options.motion_covariance || options.camera_step_covariance) && problem.lastDamping() > kMaxCovarianceDamping)
    problem.computeStep(1e-9, &dx, &dp);
  if (options.motion_covariance) StoreMotionCovariances(problem, graph);
  if (options.camera_step_covariance) summary.camera_step_covariances = problem.cameraStepCovariances(options.first_frame);
  return summary;
}

}  // namespace dslam
