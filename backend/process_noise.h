#pragma once
// Each object's motion-smoothness process noise, estimated from its own residuals (docs/design.md §2).
// The configured sigmas (noise.smoothness_sigma_*) say how much an object's motion may change per frame.
// An object that changes more (a hard brake, a cyclist's weave) would, held to them, pull the cameras
// through its ternary factors towards a smoothness it does not have. With noise.smoothness_from_residuals,
// each object's translation and rotation sigmas are scaled by s = sqrt(max(1, mean squared whitened
// residual per dimension)) over its smoothness factors: a variance-component estimate of its process
// noise, never tighter than configured, so that its information reaches the cameras only as far as its
// motion is explained. Translation and rotation are scaled apart: an object's rotation usually follows
// the model closely and would hide a translation that does not.

#include "backend/backend_params.h"
#include "backend/factor_graph.h"

namespace dslam {

// An object's scales need at least this many smoothness factors; below it the configured sigmas hold.
constexpr int kMinSmoothnessFactorsForScale = 3;

// The smoothness sigmas [translation x3; rotation x3] of `object_id`: configured, times its scales.
Vec6 SmoothnessSigma(const BackendParams& params, const FactorGraph& graph, int object_id);

// A smoothness factor's residual whitened by the configured sigmas, at the graph's current values.
Vec6 ConfiguredSmoothnessResidual(const BackendParams& params, const FactorGraph& graph, const SmoothnessEntry& s);

// Adds the residual of each smoothness factor of frame `frame` whose later motion leaves the window to
// its object's final statistics (the fixed-lag smoother calls it before it erases those motions).
void AccumulateLeavingSmoothness(const BackendParams& params, int frame, FactorGraph* graph);

// Adds one smoothness factor's residual to its object's final statistics (the exact smoother, as it
// eliminates the factor).
void AccumulateFinalSmoothness(const BackendParams& params, const SmoothnessEntry& s, FactorGraph* graph);

// Drops the process noise of objects with no motion variable left (the smoother let their track go): one that
// comes back starts afresh, and memory stays bounded by the window.
void ForgetObjectsWithoutMotions(FactorGraph* graph);

// Re-estimates every object's scales from its final statistics and the smoothness factors of frames
// [first_frame, last_frame] at the current values. Returns the largest relative change of a scale
// (0 when nothing changed or the option is off).
double UpdateSmoothnessScales(const BackendParams& params, int first_frame, int last_frame, FactorGraph* graph);

}  // namespace dslam
