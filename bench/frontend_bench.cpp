// Front-end milliseconds per frame at KITTI's 1242x375 for each flow method, on one core, and the
// back-end's milliseconds per frame (dslam run's back-end stage: classifier and ours in the sliding window) on
// the same measurements.
// Usage: bench_frontend [DATASET_DIR] [frames=60] [CONFIG.yaml] [backend_runs=1]
// Without DATASET_DIR it renders the built-in city (needs Xvfb or a display) into a scratch folder.
// Frames are read into memory first (with the configuration's mask source applied): the figures are the
// front-end's own work, not PNG decoding or mask making.
// The back-end runs backend_runs times on the same measurements; its median and p99 are over every
// frame of every run, which steadies them on a shared machine.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <numeric>
#include <sstream>

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include "bench/percentile.h"
#include "bench/rendered_city.h"
#include "data/frame_memory.h"
#include "data/image_dataset.h"
#include "frontend/image_frontend.h"
#include "pipeline/config_yaml.h"
#include "pipeline/mask_source.h"
#include "pipeline/online_backend.h"
#include "pipeline/run_config.h"
#include "pipeline/run_defaults.h"

namespace {
using Clock = std::chrono::steady_clock;

using dslam::bench::Percentile;
}  // namespace

int main(int argc, char** argv) {
  dslam::KeepFrameBuffersInHeap();  // as dslam runs (data/frame_memory.h)
  std::string dir = argc > 1 ? argv[1] : "";
  const int max_frames = argc > 2 ? std::atoi(argv[2]) : 60;
  if (max_frames < 3) {
    std::cerr << "usage: bench_frontend [DATASET_DIR] [frames >= 3] [CONFIG.yaml] [backend_runs >= 1]\n";
    return 2;
  }
  dir = dslam::bench::DatasetOrRenderedCity(dir, max_frames, "dslam_bench_frontend_city");
  if (dir.empty()) return 1;
  cv::setNumThreads(1);  // the target is for one core
  // dslam run's defaults (smoothed, window:10), then the file's keys over them, as dslam run layers them.
  const dslam::RunConfig run_defaults = dslam::DefaultRunConfig(dslam::EntryPoint::kRun);
  const dslam::RunConfig base = argc > 3 && *argv[3] ? dslam::LoadRunConfig(argv[3], run_defaults) : run_defaults;
  const int backend_runs = argc > 4 ? std::atoi(argv[4]) : 1;
  if (backend_runs < 1) {
    std::cerr << "backend_runs must be at least 1\n";
    return 2;
  }
  dslam::RunConfig config = base;
  const dslam::ImageDataset data(dir, config.dataset);
  const int frames = std::min(max_frames, data.size());
  std::vector<dslam::ImageFrame> images;
  for (int k = 0; k < frames; ++k) {
    images.push_back(data.read(k));
    dslam::ApplyMaskSource(dslam::MaskSourceOf(config), data.camera(), images.back());  // e.g. masks from the LiDAR, untimed
  }
  {  // DIS fields stand in for a dataset's precomputed flow
    auto dis = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_FAST);
    for (int k = 0; k + 1 < frames; ++k) {
      cv::Mat a, b;
      cv::cvtColor(images[k].image, a, cv::COLOR_BGR2GRAY);
      cv::cvtColor(images[k + 1].image, b, cv::COLOR_BGR2GRAY);
      dis->calc(a, b, images[k].flow_to_next);
    }
  }
  std::printf("front-end on %d frames of %s at %dx%d, one thread\n", frames, dir.c_str(), data.camera().width,
              data.camera().height);
  std::printf("%-12s %10s %10s %10s %14s %14s\n", "flow", "mean ms", "median ms", "p95 ms", "static pts", "object pts");
  std::vector<dslam::FrameMeasurement> lk_measurements;
  std::vector<double> lk_phases[9];  // FrontendFrameStats::PhaseTimes, in its order
  for (dslam::FlowMethod method :
       {dslam::FlowMethod::kLucasKanade, dslam::FlowMethod::kDis, dslam::FlowMethod::kPrecomputed}) {
    dslam::FrontendParams params = config.frontend;
    params.flow.method = method;
    dslam::ImageFrontend frontend(params, data.camera());
    std::vector<double> ms;
    double static_points = 0, object_points = 0;
    for (const auto& frame : images) {
      const auto t0 = Clock::now();
      dslam::FrameMeasurement m = frontend.process(frame);
      ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      static_points += m.static_points.size();
      for (const auto& o : m.objects) object_points += o.points.size();
      if (method == dslam::FlowMethod::kLucasKanade) {
        lk_measurements.push_back(std::move(m));
        const auto& p = frontend.lastStats().phase_ms;
        const double values[] = {p.prepare_ms, p.flow_ms,    p.refine_ms,    p.warped_ms,     p.keep_ms,
                                 p.pnp_ms,     p.objects_ms, p.replenish_ms, p.measurement_ms};
        for (size_t i = 0; i < std::size(values); ++i) lk_phases[i].push_back(values[i]);
      }
    }
    std::printf("%-12s %10.1f %10.1f %10.1f %14.0f %14.0f\n", dslam::ToString(method).c_str(),
                std::accumulate(ms.begin(), ms.end(), 0.0) / ms.size(), Percentile(ms, 0.5), Percentile(ms, 0.95),
                static_points / frames, object_points / frames);
  }

  {
    const char* names[] = {"prepare", "flow", "refine", "warped", "keep", "pnp", "objects", "replenish", "measurement"};
    std::printf("lk front-end phases, median (p95) ms:");
    for (size_t i = 0; i < std::size(names); ++i)
      std::printf(" %s %.1f (%.1f)%s", names[i], Percentile(lk_phases[i], 0.5), Percentile(lk_phases[i], 0.95),
                  i + 1 < std::size(names) ? "," : "\n");
  }

  // Per frame, as dslam run's back-end stage does it (pipeline/online_backend.h): label the frame with the
  // scene-flow classifier, add it (build, marginalise, solve) and read its online estimate.
  // A sliding window's first W frames fill it and cost less than the rest: those from W on are also given
  // on their own (the steady state, when the run is long enough to have one).
  const int filled_from =
      config.backend.schedule.kind == dslam::ScheduleKind::kSlidingWindow ? config.backend.schedule.window_frames : 0;
  std::vector<double> backend_ms, filled_ms;
  double total_ms = 0.0;
  for (int run = 0; run < backend_runs; ++run) {
    dslam::OnlineBackend backend(config, data.frameRateHz(), nullptr, /*collect=*/false);
    int k = 0;
    for (dslam::FrameMeasurement m : lk_measurements) {  // a copy: the backend labels it in place
      const auto t0 = Clock::now();
      backend.add(&m);
      backend_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      total_ms += backend_ms.back();
      if (k++ >= filled_from) filled_ms.push_back(backend_ms.back());
    }
    backend.finish();
  }
  std::printf("back-end (ours, %s, %s, classifier included) on the lk measurements, %d run(s): mean %.1f, median %.1f, "
              "p99 %.1f ms per frame",
              dslam::ToString(config.backend.default_mode).c_str(), dslam::ToString(config.backend.schedule).c_str(),
              backend_runs, total_ms / backend_ms.size(), Percentile(backend_ms, 0.5), Percentile(backend_ms, 0.99));
  if (filled_from > 0 && !filled_ms.empty())
    std::printf("; from frame %d on (window full): median %.1f, p99 %.1f", filled_from, Percentile(filled_ms, 0.5),
                Percentile(filled_ms, 0.99));
  std::printf("\n");
  return 0;
}
