#pragma once
// What leaves the fixed-lag smoother's window, and how its information stays behind.
//
// The smoother keeps two windows ending at the newest frame k: cameras and static structure over the
// last W frames, per-frame object points and object motions over the last L <= W (the object window).
// When a frame leaves a window its variables are eliminated and their factors folded into priors on
// what they were connected to, linearised at the leaving variables' last estimates. The fold is
// sparsified: correlations that would couple many in-window variables through one leaving variable
// are dropped, so that every prior keeps the graph's structure (and the solver's cost) unchanged:
//  - a leaving frame's measurement of a landmark that is still observed is held as a robust factor on
//    the landmark (camera at its final estimate) for landmark_history_frames frames, so that its Huber
//    weight follows the landmark's estimate, then becomes part of a Gaussian prior on that landmark with
//    the weight it has then: the landmark keeps everything it was ever seen from, at the cost of one 3x3
//    prior and the held measurements;
//  - a per-frame object point leaving the object window is marginalised exactly over its measurement
//    and the ternary factor to its successor, with the factors that involve nothing else still in the
//    window (its prior, the factor from its predecessor with that motion at its estimate, the linear
//    factor its predecessor left with that camera held) folded in: what remains is a 6-row linear
//    factor on (its camera, its successor, the motion into the successor's frame), so the camera keeps
//    the object's constraint and the object point carries its whole history like a Kalman filter;
//  - a leaving camera is held at its final estimate in the odometry factor to the next camera (the
//    window's anchor) and in the linear factors left by its object points, a leaving motion likewise in
//    the smoothness factor to the next motion. With BackendParams::camera_prior_by_schur (off, see
//    there for the figures) a leaving camera is instead eliminated exactly, by a Schur complement
//    (backend/linear_elimination.h), with the static landmarks that only it still measures, over its
//    own prior, its odometry factor to the next camera and their measurements and priors: what remains
//    is a 6x6 Gaussian prior on the next camera (FactorGraph::camera_prior), linearised where it was
//    made and kept there (first-estimate Jacobian), which replaces the odometry into that camera. Sparsified: the measurements of landmarks
//    still observed stay with those landmarks, camera held (above), and the linear factors left by its
//    object points hold it at its final estimate.
// Final estimates are handed to the sink as they leave. With BackendParams::marginalisation exact, none of
// this applies: backend/exact_marginalisation.h eliminates what leaves by one Schur complement instead.

#include <optional>
#include <vector>

#include "backend/backend_params.h"
#include "backend/estimate.h"
#include "backend/factor_graph.h"
#include "backend/linear_elimination.h"

namespace dslam {

// The centroid of the estimates of those point variables still in the graph (none: nullopt).
std::optional<Vec3> Centroid(const FactorGraph& graph, const std::vector<int>& vars);

// The rows of a landmark's prior and held measurements at its estimate (their Gauss-Newton information and
// gradient in square-root form), as a factor on `key`.
JacobianFactor PointPriorRows(int key, const PointVariable& var, const HuberLoss& huber);

// The estimate of one object transition from the graph's current values (velocity from the centroid
// of the tracks at k-1: the frozen one once those variables left the window).
ObjectMotionEstimate MotionEstimateOf(const FactorGraph& graph, const ObjectTransition& transition,
                                      double frame_rate_hz);

// Standard deviation of the speed of an object's centroid under `motion`, from the motion's marginal
// covariance (metres per second; 0 when the covariance is unknown).
double SpeedSigmaMps(const MotionVariable& motion, const Vec3& centroid_prev_world, const Vec3& velocity_per_frame,
                     double frame_rate_hz);

// Which objects leave with a frame. An object whose motion is one variable for its whole track (constant
// mode) keeps its per-frame points for the whole camera window: eliminating them earlier would hold its
// cameras and its motion at estimates that are still moving, and that motion is what ties its frames
// together. Objects with a motion per frame (per-step, smoothed) leave the shorter object window.
enum class ObjectWindow { kPerFrameMotion, kTrackMotion, kAll };
ObjectWindow ObjectWindowOf(const BackendParams& params, int object_id);

// Frame m leaves the object window of the objects `which` selects: their per-frame object points at m are
// marginalised, their transitions into m are final (sent to the sink) and motions no longer referenced
// are retired. A transition on an object's one motion for its whole track is final when that motion
// leaves (its track ended), with the motion's final value.
void MarginaliseObjectFrame(const BackendParams& params, double frame_rate_hz, int m, FactorGraph* graph,
                            EstimateSink* sink, ObjectWindow which = ObjectWindow::kAll);

// Frame m leaves the camera window: its camera is final, its remaining measurements are folded into
// their landmarks' priors (or retired with the landmark), and frames before m are dropped (camera m
// stays, held constant, as the anchor of the next window).
void MarginaliseCameraFrame(const BackendParams& params, int m, FactorGraph* graph, EstimateSink* sink);

}  // namespace dslam
