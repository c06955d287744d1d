#pragma once
// A learned instance segmenter's errors, applied to exact instance masks, seeded and reproducible (the
// front-end study, `dslam study`): per object and frame it may
//  - miss the object (more often when it is small: far or mostly hidden),
//  - put its boundary a few pixels in or out (erosion, or dilation bleeding onto the background),
//  - give its bounding box instead of its shape,
//  - split it in two instances (left and right of its box's middle),
//  - merge it into an overlapping neighbour (the neighbour's id),
//  - switch its id for good (the tracker lost it), or give it a fresh id for this frame only (not tracked).
// The defaults reproduce the paper's Mask R-CNN figure on KITTI cars, mIoU 0.632: 0.647 / 0.628 / 0.613 on the
// first 100 frames of rendered KITTI 0000 / 0003 / 0005 (bench_mask_degrader).
// A new id says where it comes from: object id + kDegradedIdStride * n (n >= 1), so that the study can
// give the ground truth the ids the segmenter gave.

#include <cstdint>
#include <map>

#include <opencv2/core.hpp>

namespace dslam {

constexpr int kDegradedIdStride = 2048;  // object ids of the exact masks must be below it

struct MaskDegraderParams {
  double miss_rate = 0.08;            // probability to miss an object of any size
  double miss_rate_small = 0.5;       // ... plus this much for a small one, fading with its area:
  double small_area_frac = 0.002;     //     miss_rate_small * exp(-area / (small_area_frac * image area))
  double boundary_frac = 0.17;        // boundary moved by up to this fraction of sqrt(area), in or out
  double box_rate = 0.10;             // mask replaced by its bounding box
  double split_rate = 0.03;
  double merge_rate = 0.10;           // of an object whose box overlaps another's
  double id_switch_rate = 0.02;       // a new id from this frame on
  double untracked_rate = 0.03;       // a fresh id for this frame only
  uint64_t seed = 1;
  void validate() const;              // rates in [0, 1], fractions in [0, 1]; throws std::invalid_argument
};

// What became of the exact masks' objects in one frame.
struct DegradedMaskFrame {
  cv::Mat ids;                     // CV_32S, 0 = background
  std::map<int, int> source_of;    // each id in `ids` -> the exact mask's object id it comes from
  int missed = 0, boxes = 0, splits = 0, merges = 0, switches = 0, untracked = 0;  // events of this frame
};

class MaskDegrader {
 public:
  explicit MaskDegrader(const MaskDegraderParams& params);
  // Frame k's exact instance ids (CV_16U or CV_32S); frames in increasing order (id switches last). The
  // randomness of frame k depends on the seed and k only, apart from the switched ids carried over.
  DegradedMaskFrame degrade(int k, const cv::Mat& exact_ids);

 private:
  MaskDegraderParams params_;
  std::map<int, int> switched_;  // object id -> the id it has now, after a switch
  int next_generation_ = 1;
};

// Intersection over union of each exact object (area >= min_area_px) with the degraded instance that
// overlaps it most (0 when missed), summed over frames: the mean (mIoU), and the share of objects found
// (IoU >= 0.5, the detection rate).
struct SegmentationScore {
  double iou_sum = 0.0;
  int found = 0, instances = 0;
  void add(const cv::Mat& exact_ids, const cv::Mat& degraded_ids, int min_area_px);
  double miou() const { return instances ? iou_sum / instances : 0.0; }
  double detectionRate() const { return instances ? static_cast<double>(found) / instances : 0.0; }
};

}  // namespace dslam
