#pragma once
// The factor graph of the first frames of the simulated city, labelled by the classifier as the pipeline
// labels them: a small graph with static structure, moving and parked objects for back-end tests.

#include <vector>

#include "backend/graph_builder.h"
#include "frontend/dynamic_object_classifier.h"
#include "simulation/scenarios.h"

namespace dslam::test {

inline std::vector<FrameMeasurement> LabelledCityFrames(int frames) {
  ScenarioOptions opt;
  opt.num_frames = frames;
  const Sequence seq = MakeScenario("city", opt);
  std::vector<FrameMeasurement> labelled = seq.frames;
  LabelDynamicObjects(ClassifierParams{}, seq.frame_rate_hz, &labelled);
  return labelled;
}

inline FactorGraph GraphOf(const std::vector<FrameMeasurement>& frames, const BackendParams& params) {
  FactorGraph graph;
  GraphBuilder builder(params, BuilderOptions{}, &graph);
  for (const auto& f : frames) builder.addFrame(f);
  return graph;
}

inline FactorGraph CityGraph(int frames, const BackendParams& params) {
  return GraphOf(LabelledCityFrames(frames), params);
}

}  // namespace dslam::test
