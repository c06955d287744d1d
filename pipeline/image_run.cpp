#include "pipeline/image_run.h"

#include <algorithm>
#include <chrono>
#include <set>

namespace dslam {

Sequence RunImageFrontend(const ImageDataset& dataset, const RunConfig& config, int max_frames, std::ostream* progress,
                          ImageRunSummary* summary, std::ostream* frame_log) {
  config.validate();
  const int frames = max_frames > 0 ? std::min(max_frames, dataset.size()) : dataset.size();
  FrontendParams frontend_params = config.frontend;
  frontend_params.frame_interval_s = 1.0 / dataset.frameRateHz();
  ImageFrontend frontend(frontend_params, dataset.camera());
  Sequence seq;
  seq.name = dataset.name();
  seq.frame_rate_hz = dataset.frameRateHz();
  std::set<std::pair<int, int>> visible;  // (frame, mask label) large enough to be an object
  ImageRunSummary s;
  std::vector<double> fb_medians;
  using Clock = std::chrono::steady_clock;
  double read_s = 0.0, frontend_s = 0.0;
  const auto start = Clock::now();
  for (int k = 0; k < frames; ++k) {
    const auto t0 = Clock::now();
    const ImageFrame frame = dataset.read(k);
    const auto t1 = Clock::now();
    seq.frames.push_back(frontend.process(frame));
    const auto t2 = Clock::now();
    read_s += std::chrono::duration<double>(t1 - t0).count();
    frontend_s += std::chrono::duration<double>(t2 - t1).count();
    const FrontendFrameStats& st = frontend.lastStats();
    for (int label : st.mask_labels) visible.insert({k, label});
    if (frame_log) {
      if (k == 0)
        *frame_log << "frame,object_id,flowed,tracked,added,measured,motion_rejected,pnp_inliers,median_fb_px\n";
      *frame_log << k << ",0,-1," << st.static_tracked << ',' << st.static_new << ",1,0," << st.pnp_inliers << ','
                 << st.median_fb_error_px << '\n';
      for (const auto& [id, c] : st.object_counts)
        *frame_log << k << ',' << id << ',' << c.flowed << ',' << c.tracked << ',' << c.added << ','
                   << (c.measured ? 1 : 0) << ',' << (c.motion_rejected ? 1 : 0) << ',' << st.pnp_inliers << ','
                   << st.median_fb_error_px << '\n';
    }
    s.mean_static_tracks += st.static_tracked + st.static_new;
    s.mean_object_points += st.object_points_tracked + st.object_points_new;
    s.mean_pnp_inliers += st.pnp_inliers;
    if (k > 0) fb_medians.push_back(st.median_fb_error_px);
    if (progress && ((k + 1) % std::max(1, frames / 10) == 0 || k + 1 == frames)) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
      *progress << "  front-end: frame " << k + 1 << "/" << frames << ", " << (k + 1) / elapsed << " frames/s, "
                << st.static_tracked << " static tracks kept + " << st.static_new << " new, " << st.objects
                << " objects" << std::endl;
    }
  }
  s.frames = frames;
  if (frames > 0) {
    s.frontend_ms_per_frame = 1000.0 * frontend_s / frames;
    s.read_ms_per_frame = 1000.0 * read_s / frames;
    s.mean_static_tracks /= frames;
    s.mean_object_points /= frames;
    s.mean_pnp_inliers /= std::max(1, frames - 1);
  }
  if (!fb_medians.empty()) {
    std::nth_element(fb_medians.begin(), fb_medians.begin() + fb_medians.size() / 2, fb_medians.end());
    s.median_fb_error_px = fb_medians[fb_medians.size() / 2];
  }
  if (dataset.groundTruth()) {
    s.has_ground_truth = true;
    seq.gt = ToGroundTruth(*dataset.groundTruth(), frames, config.frontend.object_max_distance_m,
                           [&](int k, int id) { return visible.count({k, id}) > 0; });
  }
  if (summary) *summary = s;
  return seq;
}

}  // namespace dslam
