#include "data/mask_degrader.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace dslam {

void MaskDegraderParams::validate() const {
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"miss_rate", miss_rate}, {"miss_rate_small", miss_rate_small},
        {"small_area_frac", small_area_frac}, {"boundary_frac", boundary_frac}, {"box_rate", box_rate},
        {"split_rate", split_rate}, {"merge_rate", merge_rate}, {"id_switch_rate", id_switch_rate},
        {"untracked_rate", untracked_rate}})
    if (!(value >= 0.0 && value <= 1.0))
      throw std::invalid_argument(std::string("mask degrader ") + name + " must be in [0, 1], got " + std::to_string(value));
}

MaskDegrader::MaskDegrader(const MaskDegraderParams& params) : params_(params) { params_.validate(); }

namespace {
struct ExactObject {
  int id = 0;
  int area = 0;
  cv::Rect box;
};
}  // namespace

DegradedMaskFrame MaskDegrader::degrade(int k, const cv::Mat& exact_ids) {
  if (exact_ids.empty() || exact_ids.channels() != 1 || (exact_ids.depth() != CV_16U && exact_ids.depth() != CV_32S))
    throw std::invalid_argument("frame " + std::to_string(k) + ": the mask to degrade must be 16-bit unsigned or 32-bit ids");
  cv::Mat ids;
  exact_ids.convertTo(ids, CV_32S);
  std::map<int, ExactObject> objects;
  for (int v = 0; v < ids.rows; ++v) {
    const int32_t* row = ids.ptr<int32_t>(v);
    for (int u = 0; u < ids.cols; ++u) {
      if (row[u] <= 0) continue;
      if (row[u] >= kDegradedIdStride)
        throw std::invalid_argument("frame " + std::to_string(k) + ": object id " + std::to_string(row[u]) +
                                    " is not below " + std::to_string(kDegradedIdStride));
      ExactObject& o = objects[row[u]];
      o.id = row[u];
      o.box = o.area++ == 0 ? cv::Rect(u, v, 1, 1) : (o.box | cv::Rect(u, v, 1, 1));
    }
  }
  // The randomness of frame k: its own stream, drawn in object order.
  std::mt19937_64 rng(params_.seed * 0x9E3779B97F4A7C15ULL + static_cast<uint64_t>(k) * 0xBF58476D1CE4E5B9ULL + 1);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double image_area = static_cast<double>(ids.total());
  const cv::Mat background = ids == 0;

  DegradedMaskFrame out;
  out.ids = cv::Mat::zeros(ids.size(), CV_32S);
  std::map<int, int> id_now;  // exact id -> its id in this frame (before merges)
  for (auto& [id, o] : objects) {
    const auto s = switched_.find(id);
    int now = s == switched_.end() ? id : s->second;
    if (uniform(rng) < params_.id_switch_rate) {
      now = id + kDegradedIdStride * next_generation_++;
      switched_[id] = now;
      ++out.switches;
    }
    if (uniform(rng) < params_.untracked_rate) {
      now = id + kDegradedIdStride * next_generation_++;
      ++out.untracked;
    }
    id_now[id] = now;
  }
  for (auto& [id, o] : objects) {
    // Every draw is made whatever the outcome, so that one object's fate does not shift another's.
    const double miss = uniform(rng), box = uniform(rng), boundary = uniform(rng), split = uniform(rng),
                 merge = uniform(rng);
    const double miss_p = params_.miss_rate + params_.miss_rate_small * std::exp(-o.area / (params_.small_area_frac * image_area + 1e-9));
    if (miss < miss_p) {
      ++out.missed;
      continue;
    }
    int out_id = id_now[id];
    if (merge < params_.merge_rate) {
      for (const auto& [other_id, other] : objects)
        if (other_id != id && (o.box & other.box).area() > 0) {
          out_id = id_now[other_id];
          out.source_of[out_id] = other_id;
          ++out.merges;
          break;
        }
    }
    if (!out.source_of.count(out_id)) out.source_of[out_id] = id;
    const cv::Mat own = ids == id;
    cv::Mat shape;
    if (box < params_.box_rate) {
      shape = cv::Mat::zeros(ids.size(), CV_8U);
      shape(o.box).setTo(255);
      shape &= (own | background);
      ++out.boxes;
    } else {
      const int r = static_cast<int>(std::lround((2.0 * boundary - 1.0) * params_.boundary_frac * std::sqrt(o.area)));
      shape = own;
      if (r != 0) {
        const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * std::abs(r) + 1, 2 * std::abs(r) + 1});
        if (r < 0) {
          cv::erode(own, shape, kernel);
        } else {
          cv::dilate(own, shape, kernel);
          shape &= (own | background);  // bleeds onto the background, not onto another object
        }
      }
    }
    out.ids.setTo(out_id, shape);
    if (split < params_.split_rate) {
      const int split_id = id + kDegradedIdStride * next_generation_++;
      cv::Mat right_half = cv::Mat::zeros(ids.size(), CV_8U);
      const int middle = o.box.x + o.box.width / 2;
      right_half(cv::Rect(middle, 0, ids.cols - middle, ids.rows)).setTo(255);
      out.ids.setTo(split_id, shape & right_half);
      out.source_of[split_id] = id;
      ++out.splits;
    }
  }
  return out;
}

void SegmentationScore::add(const cv::Mat& exact_ids, const cv::Mat& degraded_ids, int min_area_px) {
  cv::Mat a, b;
  exact_ids.convertTo(a, CV_32S);
  degraded_ids.convertTo(b, CV_32S);
  if (a.size() != b.size()) throw std::invalid_argument("segmentation score: masks of different sizes");
  std::map<int, int> area_a, area_b;
  std::map<std::pair<int, int>, int> inter;
  for (int v = 0; v < a.rows; ++v) {
    const int32_t* ra = a.ptr<int32_t>(v);
    const int32_t* rb = b.ptr<int32_t>(v);
    for (int u = 0; u < a.cols; ++u) {
      if (ra[u] > 0) ++area_a[ra[u]];
      if (rb[u] > 0) ++area_b[rb[u]];
      if (ra[u] > 0 && rb[u] > 0) ++inter[{ra[u], rb[u]}];
    }
  }
  for (const auto& [id, area] : area_a) {
    if (area < min_area_px) continue;
    double best = 0.0;
    for (auto it = inter.lower_bound({id, 0}); it != inter.end() && it->first.first == id; ++it)
      best = std::max(best, it->second / static_cast<double>(area + area_b[it->first.second] - it->second));
    iou_sum += best;
    found += best >= 0.5;
    ++instances;
  }
}

}  // namespace dslam
