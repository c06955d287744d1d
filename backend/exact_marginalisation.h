#pragma once
// The exact fixed-lag smoother's marginalisation (BackendParams::marginalisation = exact): when frame m
// leaves the window, every variable that nothing after m refers to leaves with it (camera m, the points
// it measured last, the object points of frame m, the motions that end at m), and every factor that
// touches one of them, the previous prior included, is linearised and eliminated by one Schur complement
// (backend/linear_elimination.h). What remains is one dense Gaussian prior (FactorGraph::dense_prior) on
// the variables they were tied to that stay: camera m+1, the landmarks still observed, the object points
// of frame m+1 and the motions still in the window.
//
// First-estimate Jacobians: a variable keeps, while it is in the prior, the linearisation point it had when
// it entered it. The factors being eliminated are linearised at the current estimate and moved, to first
// order, to those points, so that old and new information are expressed about the same point.
//
// Nothing is sparsified: the prior keeps every correlation, so its size grows with the landmarks and
// object points a leaving camera saw that are still in the window. Its cost, and how it compares with the
// sparsified window (backend/marginalisation.h), are in docs/results.md ("The exact fixed lag").

#include <vector>

#include "backend/backend_params.h"
#include "backend/estimate.h"
#include "backend/factor_graph.h"

namespace dslam {

// The keys of the variables that leave with frame m (VariableKey), in increasing order. With
// cameras_fixed (SLAM+MOT's object stage) the cameras are not variables.
std::vector<int> LeavingKeys(const FactorGraph& graph, int m, bool cameras_fixed);

// Frame m leaves the window: its variables are eliminated into the graph's dense prior (replacing the
// previous one), their factors are removed, and everything that became final goes to the sink: camera m,
// frame m's points, and the transitions whose motions left (the centroid of a transition's points at
// its first frame is fixed once they leave). Frames up to m are dropped. Call it for consecutive m.
void MarginaliseFrameExactly(const BackendParams& params, double frame_rate_hz, int m, bool cameras_fixed,
                             FactorGraph* graph, EstimateSink* sink);

}  // namespace dslam
