// Reading: milliseconds per frame to read a dataset's frames (decode the images, depth, masks,
// flow and LiDAR scan: ImageDataset::read) and, where the configuration makes masks from the LiDAR, the
// mask source's time on top (pipeline/mask_source.h); with --file, the time to parse one text mask
// (VDO-SLAM's semantic/*.txt) or flow field (.flo), or to decode one PNG (by DecodePng and by libpng alone).
// Usage: bench_reading DATASET [FRAMES (default: all)] [CONFIG.yaml] [REPEATS (default: 3)]
//        bench_reading --file MASK.txt|FLOW.flo|IMAGE.png [REPEATS (default: 10)]
// The figures are medians (and p90) over every frame of every repeat; the first repeat warms the file cache.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "bench/percentile.h"
#include "data/dense_maps.h"
#include "data/frame_memory.h"
#include "data/image_codec.h"
#include "data/image_dataset.h"
#include "pipeline/config_yaml.h"
#include "pipeline/mask_source.h"

namespace {

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A PNG's bytes decoded (read once): by DecodePng, which takes the common layouts by its own path
// (data/png_fast_decode.h), and by libpng alone, alternately.
int BenchPngDecode(const std::string& path, int repeats) {
  const std::vector<uint8_t> bytes = dslam::ReadFileBytes(path);
  if (bytes.empty()) throw std::runtime_error("cannot read " + path);
  std::vector<double> ours_ms, libpng_ms;
  for (int r = 0; r < repeats; ++r) {
    std::string error;
    auto t0 = Clock::now();
    if (dslam::DecodePng(bytes, dslam::ImageDecode::kUnchanged, &error).empty())
      throw std::runtime_error(path + ": " + error);
    ours_ms.push_back(MsSince(t0));
    t0 = Clock::now();
    dslam::DecodePngByLibpng(bytes, dslam::ImageDecode::kUnchanged);
    libpng_ms.push_back(MsSince(t0));
  }
  std::printf("%s: decoded in %.2f ms by DecodePng, %.2f ms by libpng alone (medians of %d)\n", path.c_str(),
              dslam::bench::Percentile(ours_ms, 0.5), dslam::bench::Percentile(libpng_ms, 0.5), repeats);
  return 0;
}

int BenchFile(const std::string& path, int repeats) {
  if (EndsWith(path, ".png")) return BenchPngDecode(path, repeats);
  std::vector<double> ms;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    if (EndsWith(path, ".flo"))
      dslam::ReadFlo(path);
    else
      dslam::ReadSemanticTxt(path);
    ms.push_back(MsSince(t0));
  }
  std::printf("%s: %.1f ms to parse (median of %d; p90 %.1f)\n", path.c_str(), dslam::bench::Percentile(ms, 0.5),
              repeats, dslam::bench::Percentile(ms, 0.9));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  dslam::KeepFrameBuffersInHeap();  // as dslam runs (data/frame_memory.h)
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: bench_reading DATASET [FRAMES] [CONFIG.yaml] [REPEATS]\n"
                 "       bench_reading --file MASK.txt|FLOW.flo|IMAGE.png [REPEATS]\n");
    return 2;
  }
  cv::setNumThreads(1);
  try {
    if (std::string(argv[1]) == "--file") {
      if (argc < 3) throw std::runtime_error("--file needs a path");
      const int repeats = argc > 3 ? std::atoi(argv[3]) : 10;
      if (repeats < 1) throw std::runtime_error("REPEATS must be at least 1");
      return BenchFile(argv[2], repeats);
    }
    const dslam::RunConfig config = argc > 3 && *argv[3] ? dslam::LoadRunConfig(argv[3]) : dslam::RunConfig{};
    const dslam::ImageDataset data(argv[1], config.dataset);
    const int frames = std::min(argc > 2 && std::atoi(argv[2]) > 0 ? std::atoi(argv[2]) : data.size(), data.size());
    const int repeats = argc > 4 ? std::atoi(argv[4]) : 3;
    if (repeats < 1) throw std::runtime_error("REPEATS must be at least 1");
    const bool masks_from_lidar = config.masks.source == dslam::MaskSourceKind::kLidarClusters;
    std::vector<double> read_ms, mask_ms, total_ms;
    for (int r = 0; r < repeats; ++r) {
      for (int k = 0; k < frames; ++k) {
        const auto t0 = Clock::now();
        dslam::ImageFrame frame = data.read(k);
        const double read = MsSince(t0);
        const auto t1 = Clock::now();
        if (masks_from_lidar) dslam::ApplyMaskSource(dslam::MaskSourceOf(config), data.camera(), frame);
        const double masks = MsSince(t1);
        read_ms.push_back(read);
        mask_ms.push_back(masks);
        total_ms.push_back(read + masks);
      }
    }
    using dslam::bench::Percentile;
    std::printf("%s (%s layout, %dx%d), %d frames x %d, read %.1f ms a frame (median; p90 %.1f)",
                argv[1], data.layout().c_str(), data.camera().width, data.camera().height, frames, repeats,
                Percentile(read_ms, 0.5), Percentile(read_ms, 0.9));
    if (masks_from_lidar)
      std::printf(", masks from the LiDAR %.1f (p90 %.1f), both %.1f (p90 %.1f)", Percentile(mask_ms, 0.5),
                  Percentile(mask_ms, 0.9), Percentile(total_ms, 0.5), Percentile(total_ms, 0.9));
    std::printf("\n");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_reading: %s\n", e.what());
    return 2;
  }
}
