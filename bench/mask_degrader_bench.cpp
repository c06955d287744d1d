// The degraded segmenter of `dslam study` on a dataset's exact masks: its mIoU, detection rate and error
// counts, for calibrating its defaults against the paper's Mask R-CNN figures (mIoU 0.632 for KITTI cars).
// Usage: bench_mask_degrader DATASET [FRAMES (default 100)] [PARAM=VALUE ...]
//   PARAM: miss_rate, miss_rate_small, small_area_frac, boundary_frac, box_rate, split_rate, merge_rate,
//          id_switch_rate, untracked_rate, seed
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <string>

#include "data/frame_memory.h"
#include "data/image_dataset.h"
#include "data/mask_degrader.h"
#include "pipeline/run_config.h"

int main(int argc, char** argv) {
  dslam::KeepFrameBuffersInHeap();  // as dslam runs (data/frame_memory.h)
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_mask_degrader DATASET [FRAMES] [PARAM=VALUE ...]\n");
    return 2;
  }
  try {
    dslam::MaskDegraderParams p;
    const std::map<std::string, double*> fields = {
        {"miss_rate", &p.miss_rate},       {"miss_rate_small", &p.miss_rate_small}, {"small_area_frac", &p.small_area_frac},
        {"boundary_frac", &p.boundary_frac}, {"box_rate", &p.box_rate},           {"split_rate", &p.split_rate},
        {"merge_rate", &p.merge_rate},     {"id_switch_rate", &p.id_switch_rate},   {"untracked_rate", &p.untracked_rate}};
    int frames = 100;
    for (int i = 2; i < argc; ++i) {
      const std::string arg = argv[i];
      const size_t eq = arg.find('=');
      if (eq == std::string::npos) {
        frames = std::atoi(argv[i]);
      } else if (arg.substr(0, eq) == "seed") {
        p.seed = std::strtoull(arg.c_str() + eq + 1, nullptr, 10);
      } else if (fields.count(arg.substr(0, eq))) {
        *fields.at(arg.substr(0, eq)) = std::atof(arg.c_str() + eq + 1);
      } else {
        std::fprintf(stderr, "unknown parameter %s\n", arg.c_str());
        return 2;
      }
    }
    dslam::ImageDatasetOptions options;
    options.read_flow = false;
    const dslam::ImageDataset data(argv[1], options);
    const int min_area =
        static_cast<int>(dslam::RunConfig{}.frontend.min_mask_area_pct / 100.0 * data.camera().width * data.camera().height);
    dslam::MaskDegrader degrader(p);
    dslam::SegmentationScore score;
    int missed = 0, boxes = 0, splits = 0, merges = 0, switches = 0, untracked = 0;
    frames = std::min(frames, data.size());
    for (int k = 0; k < frames; ++k) {
      const cv::Mat ids = data.read(k).instance_ids;
      const dslam::DegradedMaskFrame d = degrader.degrade(k, ids);
      score.add(ids, d.ids, std::max(1, min_area));
      missed += d.missed, boxes += d.boxes, splits += d.splits, merges += d.merges, switches += d.switches,
          untracked += d.untracked;
    }
    std::printf("%s, %d frames: mIoU %.3f, detection rate %.3f over %d object instances; missed %d, boxes %d, "
                "splits %d, merges %d, id switches %d, untracked %d\n",
                argv[1], frames, score.miou(), score.detectionRate(), score.instances, missed, boxes, splits, merges,
                switches, untracked);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_mask_degrader: %s\n", e.what());
    return 2;
  }
}
