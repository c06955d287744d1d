#include "pipeline/streamed_run.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>

#include "output/object_summary.h"
#include "pipeline/lockstep_methods.h"
#include "pipeline/method_output.h"

namespace dslam {

StreamedRunResult RunStreamed(SensorSimulator* simulator, const RunConfig& config, const StreamedRunOptions& options) {
  std::error_code ec;
  std::filesystem::create_directories(options.out_dir, ec);
  if (ec) throw std::runtime_error("cannot create output directory " + options.out_dir + ": " + ec.message());
  const GroundTruth& gt = simulator->groundTruth();
  const double rate = simulator->frameRateHz();

  MethodOutputs outputs = MakeMethodOutputs(options.methods, options.out_dir, &gt, rate, options.object_category);
  std::map<Method, EstimateSink*> sinks;
  for (auto& [method, output] : outputs) sinks[method] = output.get();
  LockstepMethods methods(config, rate, sinks);

  const int total = simulator->numFrames();
  const int step = std::max(1, total / 10);
  std::vector<int64_t> t_ns;
  t_ns.reserve(total);
  while (!simulator->done()) {
    FrameMeasurement frame = simulator->next();
    const int k = frame.frame_index;
    const int64_t stamp = frame.t_ns;
    t_ns.push_back(stamp);
    for (auto& [method, output] : outputs) output->frameMade(k, stamp);
    const std::optional<FrameEstimate> latest = methods.add(&frame);
    if (latest) outputs.at(Method::kOurs)->onlinePose(stamp, latest->T_world_camera);
    if (options.progress && ((k + 1) % step == 0 || k + 1 == total))
      *options.progress << "  frame " << k + 1 << "/" << total << std::endl;
    if (options.after_frame) options.after_frame(k + 1);
  }
  methods.finish();

  StreamedRunResult result;
  result.outcomes =
      FinishMethodOutputs(outputs, [&](Method m) { return methods.wallTimeS(m); }, &result.ours_objects);
  WriteGroundTruthFiles(options.out_dir, gt, t_ns);
  if (outputs.count(Method::kOurs)) WriteObjectsCsv(options.out_dir + "/objects.csv", result.ours_objects);
  return result;
}

}  // namespace dslam
