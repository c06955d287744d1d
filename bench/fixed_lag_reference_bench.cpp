// How far ours' sliding window is from an exact fixed-lag smoother, measured on a simulated scenario, and how
// close ours' exact marginalisation (backend.marginalisation: exact) comes to it.
//
// A fixed-lag smoother of W frames makes camera m final from the measurements of frames 0..m+W-1 (the window's
// last solve that holds it). The best any such smoother can do, whatever its marginalisation, is the optimum of
// all those measurements: the batch solve of the prefix 0..m+W-1, read at camera m. This bench computes that
// reference (one batch solve per prefix, so slow: a reference, not an estimator) and prints it beside ours'
// window and ours' batch. Motions of objects with a motion per frame are read the same way, from the prefix
// their object window ends with (frames 0..j+L-1 for the motion into j); an object's one motion for its whole
// track (constant mode) is the whole batch's, as the window reports it when the track ends (the points are the
// whole batch's too; their error is not printed). The gap between the reference and the window is what the
// window's sparsified marginalisation costs; the gap between the reference and the batch is what any fixed lag
// costs. The exact window keeps one window of W frames for every variable, so its motions per frame are made
// final later than the reference's (from frames 0..j+W-1); the gap between it and the reference in cameras is
// its linearisation.
//
// Usage: bench_fixed_lag_reference [scenario=paper] [seeds=5] [frames=0: the scenario's length]
// Prints, per seed and as RMS over the seeds, ours' camera ATE and RTE and object OMTE and OMSE, and each
// window's median back-end time a frame.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "backend/methods.h"
#include "bench/percentile.h"
#include "evaluation/evaluate_run.h"
#include "frontend/dynamic_object_classifier.h"
#include "pipeline/run_defaults.h"
#include "simulation/scenarios.h"

namespace {

struct Figures {
  double ate_m = 0.0, rte_pct = 0.0, omte_pct = 0.0, omse_pct = 0.0;
};

Figures FiguresOf(const dslam::Sequence& seq, const dslam::Estimate& estimate) {
  const dslam::MethodMetrics m = dslam::EvaluateEstimate(seq, estimate, /*estimates_objects=*/true, "");
  Figures f;
  f.ate_m = m.camera.ate_m;
  f.rte_pct = m.camera.rte_pct.value_or(0.0);
  if (m.objects) {
    f.omte_pct = m.objects->omte_pct.value_or(0.0);
    f.omse_pct = m.objects->omse_pct.value_or(0.0);
  }
  return f;
}

// The reference: camera m from the batch over frames 0..m+W-1, a per-frame motion into j from the batch over
// 0..j+L-1, the rest from the batch over everything.
dslam::Estimate FixedLagReference(const dslam::BackendParams& window_params, const dslam::BackendParams& batch,
                                  double rate_hz, const std::vector<dslam::FrameMeasurement>& frames,
                                  const dslam::Estimate& full) {
  const int n = static_cast<int>(frames.size());
  const int W = window_params.schedule.window_frames;
  const int L = std::min(window_params.object_window_frames, W);
  dslam::Estimate reference = full;
  std::map<std::pair<int, int>, size_t> motion_index;  // (object, frame) -> index in reference.object_motions
  for (size_t i = 0; i < reference.object_motions.size(); ++i)
    motion_index[{reference.object_motions[i].object_id, reference.object_motions[i].frame}] = i;
  for (int last = L - 1; last < n - 1; ++last) {
    const std::vector<dslam::FrameMeasurement> prefix(frames.begin(), frames.begin() + last + 1);
    const dslam::Estimate e = dslam::RunMethod(dslam::Method::kOurs, batch, rate_hz, prefix).estimate;
    const int camera = last - W + 1;
    if (camera >= 0) reference.T_world_camera[camera] = e.T_world_camera[camera];
    const int motion_frame = last - L + 1;
    for (const dslam::ObjectMotionEstimate& m : e.object_motions) {
      if (m.frame != motion_frame || batch.modeFor(m.object_id) == dslam::MotionMode::kConstant) continue;
      const auto it = motion_index.find({m.object_id, m.frame});
      if (it != motion_index.end()) reference.object_motions[it->second] = m;
    }
    std::fprintf(stderr, "\r  prefix %d/%d", last + 1, n);
  }
  std::fprintf(stderr, "\n");
  return reference;
}

}  // namespace

static int Run(int argc, char** argv) {
  const std::string scenario = argc > 1 ? argv[1] : "paper";
  const int seeds = argc > 2 ? std::atoi(argv[2]) : 5;
  const int num_frames = argc > 3 ? std::atoi(argv[3]) : 0;
  if (seeds < 1 || num_frames < 0) {
    std::cerr << "usage: bench_fixed_lag_reference [scenario] [seeds >= 1] [frames >= 0]\n";
    return 2;
  }
  dslam::RunConfig config = dslam::DefaultRunConfig(dslam::EntryPoint::kSim, scenario);
  dslam::BackendParams window = config.backend;
  window.schedule = dslam::DefaultRunConfig(dslam::EntryPoint::kRun).backend.schedule;  // window:10, as dslam run
  dslam::BackendParams exact = window;
  exact.marginalisation = dslam::Marginalisation::kExact;
  dslam::BackendParams batch = config.backend;
  batch.schedule.kind = dslam::ScheduleKind::kBatch;
  std::printf("%s, ours (%s), window:%d against an exact fixed lag of the same length and the batch\n",
              scenario.c_str(), dslam::ToString(window.default_mode).c_str(), window.schedule.window_frames);
  std::printf("%-6s %-10s %10s %10s %10s %10s\n", "seed", "estimate", "ATE m", "RTE %", "OMTE %", "OMSE %");
  const char* names[] = {"window", "exact", "reference", "batch"};
  constexpr int kBatch = 3;
  std::vector<std::vector<Figures>> all(4);
  for (int seed = 1; seed <= seeds; ++seed) {
    dslam::ScenarioOptions options;
    options.seed = static_cast<uint64_t>(seed);
    options.num_frames = num_frames;
    const dslam::Sequence seq = dslam::MakeScenario(scenario, options);
    std::vector<dslam::FrameMeasurement> frames = seq.frames;
    dslam::LabelDynamicObjects(config.classifier, seq.frame_rate_hz, &frames);
    const dslam::Estimate full = dslam::RunMethod(dslam::Method::kOurs, batch, seq.frame_rate_hz, frames).estimate;
    const dslam::MethodResult windowed = dslam::RunMethod(dslam::Method::kOurs, window, seq.frame_rate_hz, frames);
    const dslam::MethodResult exact_lag = dslam::RunMethod(dslam::Method::kOurs, exact, seq.frame_rate_hz, frames);
    std::printf("%-6d back-end median a frame: window %.2f ms, exact %.2f ms\n", seed,
                dslam::bench::Percentile(windowed.solve_times_ms, 0.5),
                dslam::bench::Percentile(exact_lag.solve_times_ms, 0.5));
    const dslam::Estimate reference = FixedLagReference(window, batch, seq.frame_rate_hz, frames, full);
    const dslam::Estimate* estimates[] = {&windowed.estimate, &exact_lag.estimate, &reference, &full};
    for (int i = 0; i < 4; ++i) {
      const Figures f = FiguresOf(seq, *estimates[i]);
      all[i].push_back(f);
      std::printf("%-6d %-10s %10.4f %10.3f %10.3f %10.3f\n", seed, names[i], f.ate_m, f.rte_pct, f.omte_pct,
                  f.omse_pct);
      std::fflush(stdout);
    }
  }
  auto rms = [](const std::vector<Figures>& v, double Figures::*field) {
    double sum = 0.0;
    for (const Figures& f : v) sum += f.*field * f.*field;
    return std::sqrt(sum / static_cast<double>(v.size()));
  };
  std::printf("RMS over %d seed(s), and each over the batch's:\n", seeds);
  for (int i = 0; i < 4; ++i)
    std::printf("%-6s %-10s %10.4f %10.3f %10.3f %10.3f   x batch: %.3f %.3f %.3f %.3f\n", "rms", names[i],
                rms(all[i], &Figures::ate_m), rms(all[i], &Figures::rte_pct), rms(all[i], &Figures::omte_pct),
                rms(all[i], &Figures::omse_pct), rms(all[i], &Figures::ate_m) / rms(all[kBatch], &Figures::ate_m),
                rms(all[i], &Figures::rte_pct) / rms(all[kBatch], &Figures::rte_pct),
                rms(all[i], &Figures::omte_pct) / rms(all[kBatch], &Figures::omte_pct),
                rms(all[i], &Figures::omse_pct) / rms(all[kBatch], &Figures::omse_pct));
  return 0;
}

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "bench_fixed_lag_reference: " << e.what() << "\n";
    return 1;
  }
}
