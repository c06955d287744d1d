#include "pipeline/run_sequence.h"

namespace dslam {

MethodOutcomes RunSequence(const Sequence& seq, const RunConfig& config, const RunSequenceOptions& options) {
  config.validate();
  std::vector<FrameMeasurement> frames = seq.frames;
  LabelDynamicObjects(config.classifier, seq.frame_rate_hz, &frames);

  MethodOutcomes outcomes;
  for (Method method : options.methods) {
    ProgressCallback progress;
    if (options.progress) {
      const int step = std::max<int>(1, static_cast<int>(frames.size()) / 10);
      progress = [&, method, step](int done, int total) {
        if (done % step == 0 || done == total)
          *options.progress << "  " << ToString(method) << ": frame " << done << "/" << total << std::endl;
      };
    }
    MethodOutcome outcome;
    const auto done = options.precomputed.find(method);
    outcome.result = done != options.precomputed.end() ? done->second
                                                       : RunMethod(method, config.backend, seq.frame_rate_hz, frames, progress);
    if (options.evaluate)
      outcome.metrics = EvaluateEstimate(seq, outcome.result.estimate, method != Method::kStaticOnly,
                                         options.object_category);
    outcomes[method] = std::move(outcome);
  }
  return outcomes;
}

}  // namespace dslam
