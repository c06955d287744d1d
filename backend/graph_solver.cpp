// The batch schedule's Ceres solve, and the exact fixed-lag smoother's window solve (with its prior).
#include "backend/graph_solver.h"

#include <ceres/ceres.h>

#include <memory>
#include <optional>
#include <unordered_set>

#include "backend/factors/motion_smoothness_factor.h"
#include "backend/factors/odometry_factor.h"
#include "backend/factors/point_measurement_factor.h"
#include "backend/factors/point_motion_factor.h"
#include "backend/factors/pose_block.h"
#include "backend/factors/pose_manifold.h"
#include "backend/factors/pose_prior_factor.h"
#include "backend/process_noise.h"

namespace dslam {
namespace {

// The exact smoother's prior (FactorGraph::dense_prior) for Ceres: r = r0 + R [x_i (-) lin_i]. Its Jacobian
// in each block's tangent stays R's columns (first-estimate Jacobians); Ceres asks for it in the block's
// ambient coordinates and multiplies by the manifold's Plus Jacobian P, so a pose block's columns are given
// as R_i (P^T P)^-1 P^T.
class DensePriorCost : public ceres::CostFunction {
 public:
  explicit DensePriorCost(const DensePrior& prior) : prior_(prior) {
    set_num_residuals(static_cast<int>(prior.R.rows()));
    for (int key : prior.keys)
      mutable_parameter_block_sizes()->push_back(ValueSizeOfKey(key));
  }

  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    const Eigen::Index rows = prior_.R.rows();
    Eigen::VectorXd d(prior_.R.cols());
    Eigen::Index col = 0;
    for (size_t i = 0; i < prior_.keys.size(); ++i) {
      const Eigen::VectorXd step = DensePrior::Tangent(prior_.keys[i], x[i], prior_.lin[i].data());
      d.segment(col, step.size()) = step;
      col += step.size();
    }
    Eigen::Map<Eigen::VectorXd>(residuals, rows) = prior_.r0 + prior_.R * d;
    if (!jacobians) return true;
    col = 0;
    for (size_t i = 0; i < prior_.keys.size(); ++i) {
      const int dim = TangentDimOfKey(prior_.keys[i]);
      if (jacobians[i]) {
        using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
        const int ambient = parameter_block_sizes()[i];
        Eigen::Map<RowMajor> J(jacobians[i], rows, ambient);
        if (dim == ambient) {
          J = prior_.R.middleCols(col, dim);
        } else {
          const Eigen::Matrix<double, 7, 6> P = PoseBlockPlusJacobian(x[i]);
          J = prior_.R.middleCols(col, dim) * (P.transpose() * P).inverse() * P.transpose();
        }
      }
      col += dim;
    }
    return true;
  }

 private:
  const DensePrior& prior_;
};

}  // namespace

SolveSummary SolveGraph(const BackendParams& params, const SolveOptions& options, FactorGraph* graph) {
  SolveSummary result;
  const int first = std::max(0, options.first_frame);
  const int last = std::min(options.last_frame, graph->numFrames() - 1);
  if (last < first) return result;

  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::HuberLoss huber(params.noise.huber_delta);
  std::optional<ceres::HuberLoss> smoothness_huber;
  if (params.noise.smoothness_huber_delta > 0.0) smoothness_huber.emplace(params.noise.smoothness_huber_delta);
  std::unique_ptr<ceres::Manifold> pose_manifold(NewPoseManifold());

  std::unordered_set<int> camera_blocks, point_blocks, motion_blocks;
  auto camera = [&](int k) {
    double* block = graph->camera(k);
    if (camera_blocks.insert(k).second) {
      problem.AddParameterBlock(block, kPoseBlockSize, pose_manifold.get());
      if (k < first || options.fix_cameras) problem.SetParameterBlockConstant(block);
    }
    return block;
  };
  auto point = [&](int v) {
    double* block = graph->points.at(v).p_world.data();
    if (point_blocks.insert(v).second) {
      problem.AddParameterBlock(block, 3);
      if (graph->points.at(v).last_frame < first) problem.SetParameterBlockConstant(block);
    }
    return block;
  };
  auto motion = [&](int m) {
    double* block = graph->motions.at(m).H_anchor.data();
    if (motion_blocks.insert(m).second) {
      problem.AddParameterBlock(block, kPoseBlockSize, pose_manifold.get());
      if (graph->motions.at(m).last_frame < first) problem.SetParameterBlockConstant(block);
    }
    return block;
  };

  if (first == 0 && !options.fix_cameras)
    problem.AddResidualBlock(PosePriorFactor::Create(graph->T_world_camera0_prior, graph->prior_sigma), nullptr,
                             camera(0));
  for (int k = first; k <= last; ++k) {
    const FrameFactors& factors = graph->frame(k);
    if (factors.odometry && k > 0 && !options.fix_cameras)
      problem.AddResidualBlock(OdometryFactor::Create(factors.odometry->T_prev_curr, factors.odometry->sigma), nullptr,
                               camera(k - 1), camera(k));
    for (const auto& m : factors.measurements)
      problem.AddResidualBlock(PointMeasurementFactor::Create(m.z_camera, m.sigma_m), &huber, camera(k),
                               point(m.point_var));
    for (const auto& m : factors.point_motions)
      problem.AddResidualBlock(PointMotionFactor::Create(params.noise.motion_sigma_m,
                                                         graph->motions.at(m.motion_var).anchor_world),
                               &huber, point(m.prev_point_var), point(m.curr_point_var), motion(m.motion_var));
    for (const auto& s : factors.smoothness) {
      const MotionVariable& curr = graph->motions.at(s.curr_motion_var);
      problem.AddResidualBlock(MotionSmoothnessFactor::Create(SmoothnessSigma(params, *graph, curr.object_id),
                                                              graph->motions.at(s.prev_motion_var).anchor_world,
                                                              curr.anchor_world),
                               smoothness_huber ? &*smoothness_huber : nullptr, motion(s.prev_motion_var),
                               motion(s.curr_motion_var));
    }
  }
  // The exact smoother's prior, on variables of the window; Ceres may not eliminate its points on their own.
  std::unordered_set<int> prior_points;
  if (graph->dense_prior) {
    std::vector<double*> blocks;
    for (int key : graph->dense_prior->keys) {
      const int id = IdOfKey(key);
      switch (KindOfKey(key)) {
        case VariableKind::kCamera: blocks.push_back(camera(id)); break;
        case VariableKind::kPoint: blocks.push_back(point(id)), prior_points.insert(id); break;
        case VariableKind::kMotion: blocks.push_back(motion(id)); break;
      }
    }
    problem.AddResidualBlock(new DensePriorCost(*graph->dense_prior), nullptr, blocks);
  }
  result.num_residual_blocks = problem.NumResidualBlocks();
  if (result.num_residual_blocks == 0) return result;

  // Points first, then poses and motions. Schur: the Schur complement of an independent set of
  // points (alternate points along each track chain). Cholesky: one sparse factorisation of the whole
  // system with every point ordered before the poses and motions (faster here; same solution).
  const bool schur = params.linear_solver == LinearSolver::kSchur;
  auto* ordering = new ceres::ParameterBlockOrdering;
  for (int v : point_blocks) {
    const bool first_group = !schur || (graph->points.at(v).eliminate_first && !prior_points.count(v));
    ordering->AddElementToGroup(graph->points.at(v).p_world.data(), first_group ? 0 : 1);
  }
  for (int k : camera_blocks) ordering->AddElementToGroup(graph->camera(k), 1);
  for (int m : motion_blocks) ordering->AddElementToGroup(graph->motions.at(m).H_anchor.data(), 1);

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = schur ? ceres::SPARSE_SCHUR : ceres::SPARSE_NORMAL_CHOLESKY;
  if (ordering->GroupSize(0) > 0) {
    solver_options.linear_solver_ordering.reset(ordering);
  } else {
    delete ordering;  // no point to eliminate (e.g. odometry only)
    solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  }
  // Eigen's sparse Cholesky: on these problems faster than CHOLMOD, whose OpenMP threads mostly wait.
  solver_options.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.initial_trust_region_radius = options.initial_trust_region_radius;
  solver_options.num_threads = options.num_threads;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  result.num_iterations = static_cast<int>(summary.iterations.size());
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.usable = summary.IsSolutionUsable();
  return result;
}

}  // namespace dslam
