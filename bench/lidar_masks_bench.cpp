// The LiDAR mask source (masks.source: lidar_clusters) where the truth is known: on a rendered scene, a
// scan sampled from its exact depth (masks.lidar_from_depth) gives masks that are scored against the
// scene's exact masks, over objects within 25 m whose mask covers at least frontend.min_mask_area_pct of
// the image: mIoU (each exact object against the LiDAR label that overlaps it most) and the detection rate
// (IoU >= 0.5); and the mask source's time per frame (median, one thread).
// Usage: bench_lidar_masks DATASET [FRAMES (default: all)] [CONFIG.yaml]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <stdexcept>
#include <vector>

#include "bench/percentile.h"
#include "data/frame_memory.h"
#include "data/image_dataset.h"
#include "data/mask_degrader.h"
#include "pipeline/config_yaml.h"
#include "pipeline/mask_source.h"

namespace {

// The exact mask with every object farther than `max_distance_m` (the median depth of its pixels) removed.
cv::Mat ObjectsWithin(const cv::Mat& ids, const cv::Mat& depth_m, double max_distance_m) {
  cv::Mat out;
  ids.convertTo(out, CV_32S);
  std::map<int, std::vector<float>> depths;
  for (int v = 0; v < out.rows; ++v)
    for (int u = 0; u < out.cols; ++u)
      if (out.at<int32_t>(v, u) > 0 && depth_m.at<float>(v, u) > 0.0f) depths[out.at<int32_t>(v, u)].push_back(depth_m.at<float>(v, u));
  for (auto& [id, z] : depths) {
    std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
    if (z[z.size() / 2] > max_distance_m) out.setTo(0, out == id);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  dslam::KeepFrameBuffersInHeap();  // as dslam runs (data/frame_memory.h)
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_lidar_masks DATASET [FRAMES] [CONFIG.yaml]\n");
    return 2;
  }
  try {
    dslam::RunConfig config = argc > 3 ? dslam::LoadRunConfig(argv[3]) : dslam::RunConfig{};
    config.masks.source = dslam::MaskSourceKind::kLidarClusters;
    config.masks.lidar_from_depth = true;
    dslam::ImageDatasetOptions options = config.dataset;
    options.read_flow = false;
    const dslam::ImageDataset data(argv[1], options);
    if (!data.hasMasks()) throw std::runtime_error(std::string(argv[1]) + " has no exact masks to score against");
    const int frames = std::min(argc > 2 && std::atoi(argv[2]) > 0 ? std::atoi(argv[2]) : data.size(), data.size());
    const int min_area = std::max(
        1, static_cast<int>(config.frontend.min_mask_area_pct / 100.0 * data.camera().width * data.camera().height));
    dslam::SegmentationScore score;
    std::vector<double> ms;
    for (int k = 0; k < frames; ++k) {
      dslam::ImageFrame frame = data.read(k);
      const cv::Mat exact = ObjectsWithin(frame.instance_ids, frame.depth_m, 25.0);
      const auto t0 = std::chrono::steady_clock::now();
      dslam::ApplyMaskSource(dslam::MaskSourceOf(config), data.camera(), frame);
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      score.add(exact, frame.instance_ids, min_area);
    }
    std::printf("%s, %d frames: objects within 25 m: %d instances, mIoU %.3f, detection rate (IoU >= 0.5) %.3f; "
                "mask source %.1f ms a frame (median; p90 %.1f)\n",
                argv[1], frames, score.instances, score.miou(), score.detectionRate(), dslam::bench::Percentile(ms, 0.5),
                dslam::bench::Percentile(ms, 0.9));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_lidar_masks: %s\n", e.what());
    return 2;
  }
}
