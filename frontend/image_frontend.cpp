#include "frontend/image_frontend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "frontend/mask_box_prediction.h"
#include "frontend/mask_edges.h"
#include "frontend/warped_patch_search.h"

namespace dslam {
namespace {

// An object's last motion still predicts its flow this many frames later (a short occlusion).
constexpr int kObjectMotionMemoryFrames = 5;
// Consecutive consistent fits that make an object's motion memory trusted (see acceptObjectMotion).
constexpr int kConfirmedFits = 2;

// The camera motion from PnP, fused with the odometry unless the odometry contradicts it beyond `gate_chi2`
// (a wheel slip, a corrupt record: the static points hold the camera); `*odometry_rejected` says whether it did.
SE3 FuseUnlessContradicted(const PnpEstimate& pnp, const std::optional<OdometryMeasurement>& odometry,
                           double gate_chi2, bool* odometry_rejected) {
  *odometry_rejected = odometry && OdometryDisagreementChi2(pnp, *odometry) > gate_chi2;
  return odometry && !*odometry_rejected ? FuseCameraMotion(pnp, *odometry) : pnp.T_prev_curr;
}

// Instance labels as CV_32SC1 (negative ids, as Mask R-CNN's "-1 = none", become background).
cv::Mat ToLabels(const cv::Mat& instance_ids, const cv::Size& size) {
  if (instance_ids.empty()) return cv::Mat(size, CV_32S, cv::Scalar(0));
  cv::Mat labels;
  instance_ids.convertTo(labels, CV_32S);
  if (instance_ids.depth() != CV_16U) labels.setTo(0, labels < 0);  // unsigned ids have no "none" to clear
  return labels;
}

float DepthAt(const cv::Mat& depth, const cv::Point2f& px) {
  const int u = static_cast<int>(std::lround(px.x)), v = static_cast<int>(std::lround(px.y));
  if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) return 0.0f;
  const float z = depth.at<float>(v, u);
  return std::isfinite(z) ? z : 0.0f;
}

int LabelAt(const cv::Mat& labels, const cv::Point2f& px) {
  const int u = static_cast<int>(std::lround(px.x)), v = static_cast<int>(std::lround(px.y));
  if (u < 0 || v < 0 || u >= labels.cols || v >= labels.rows) return 0;
  return labels.at<int32_t>(v, u);
}

double Median(std::vector<float> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// Where new points of `label` (0: the background) may go inside `region`, region-sized: its pixels,
// with depth in [min_depth_m, max_depth_m], not near a mask edge. One pass (it ran as five whole-image
// matrix expressions).
cv::Mat NewPointMask(const cv::Mat& labels, const cv::Mat& depth, const cv::Mat& near_edge, const cv::Rect& region,
                     int label, double min_depth_m, double max_depth_m) {
  cv::Mat allowed(region.size(), CV_8UC1);
  const float lo = static_cast<float>(min_depth_m);
  const float hi = std::isfinite(max_depth_m) ? static_cast<float>(max_depth_m) : std::numeric_limits<float>::infinity();
  for (int v = 0; v < region.height; ++v) {
    const int32_t* l = labels.ptr<int32_t>(region.y + v) + region.x;
    const float* z = depth.ptr<float>(region.y + v) + region.x;
    const uint8_t* edge = near_edge.ptr<uint8_t>(region.y + v) + region.x;
    uint8_t* out = allowed.ptr<uint8_t>(v);
    for (int u = 0; u < region.width; ++u) out[u] = (l[u] == label && z[u] >= lo && z[u] <= hi && !edge[u]) ? 255 : 0;
  }
  return allowed;
}

// Milliseconds since the last lap (or construction), for FrontendFrameStats::phase_ms.
class PhaseClock {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
    return ms;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

ImageFrontend::ImageFrontend(const FrontendParams& params, const PinholeCamera& camera)
    : params_(params), camera_(camera), flow_(params.flow), associator_(params.association) {
  params_.validate();
  if (camera_.width <= 0 || camera_.height <= 0 || !(camera_.fx > 0.0) || !(camera_.fy > 0.0))
    throw std::invalid_argument("front-end camera needs a positive size and focal lengths");
}

struct ImageFrontend::Snapshot {
  std::vector<Track> tracks;
  std::map<int, cv::Rect> prev_label_boxes;
  std::optional<SE3> last_camera_motion;
  std::map<int, ObjectMotionMemory> last_object_motion;
  GreyPyramid prev_grey;  // headers, as the two below: process() replaces them, never writes into them
  cv::Mat prev_depth, prev_flow_to_next;
  std::optional<int> prev_frame_index;
  int64_t prev_t_ns = 0;
  int64_t next_track_id = 1;
  ObjectAssociator associator;
  FrontendFrameStats stats;
};

ImageFrontend::Snapshot ImageFrontend::save() const {
  return {tracks_,     prev_label_boxes_,  last_camera_motion_, last_object_motion_, prev_grey_,    prev_depth_,
          prev_flow_to_next_, prev_frame_index_, prev_t_ns_, next_track_id_, associator_, stats_};
}

void ImageFrontend::restore(Snapshot&& s) {
  tracks_ = std::move(s.tracks);
  prev_label_boxes_ = std::move(s.prev_label_boxes);
  last_camera_motion_ = s.last_camera_motion;
  last_object_motion_ = std::move(s.last_object_motion);
  prev_grey_ = std::move(s.prev_grey);
  prev_depth_ = s.prev_depth;
  prev_flow_to_next_ = s.prev_flow_to_next;
  prev_frame_index_ = s.prev_frame_index;
  prev_t_ns_ = s.prev_t_ns;
  next_track_id_ = s.next_track_id;
  associator_ = s.associator;
  stats_ = std::move(s.stats);
}

ImageFrontend::~ImageFrontend() = default;

PreparedFrame ImageFrontend::Prepare(const FrontendParams& params, const ImageFrame& frame) {
  if (const std::string bad = FindInvalidImageFrame(frame); !bad.empty()) throw std::invalid_argument(bad);
  PreparedFrame out;
  const cv::Mat gray = GreyImage(frame.image);
  out.labels = ToLabels(frame.instance_ids, gray.size());
  const cv::Mat& labels = out.labels;

  // Mask labels large enough to be objects, with their bounding boxes (later work stays inside them).
  std::map<int, int>& label_areas = out.label_areas;
  std::map<int, cv::Rect>& label_boxes = out.label_boxes;
  for (int v = 0; v < labels.rows; ++v) {
    const int32_t* row = labels.ptr<int32_t>(v);
    for (int u = 0; u < labels.cols;) {
      if (row[u] <= 0) {
        ++u;
        continue;
      }
      int end = u + 1;  // a run of one label: one map update per run, not per pixel
      while (end < labels.cols && row[end] == row[u]) ++end;
      label_areas[row[u]] += end - u;
      cv::Rect& box = label_boxes[row[u]];
      box = box.empty() ? cv::Rect(u, v, end - u, 1) : (box | cv::Rect(u, v, end - u, 1));
      u = end;
    }
  }
  const double min_area = params.min_mask_area_pct / 100.0 * labels.total();
  for (auto it = label_areas.begin(); it != label_areas.end();) it = it->second < min_area ? label_areas.erase(it) : ++it;

  // Pixels near a mask edge mix the depths of object and background, and a point tracked there may be
  // sliding along an occluding contour: no points are kept or created there.
  out.near_edge = NearMaskEdge(labels, params.mask_border_px);
  // This frame's pyramid, built once: every search from the previous frame and, next frame, from this one reads it.
  out.grey = BuildGreyPyramid(params.flow, gray);
  out.background_allowed = NewPointMask(labels, frame.depth_m, out.near_edge, cv::Rect(0, 0, gray.cols, gray.rows), 0,
                                        params.static_min_depth_m, params.static_max_depth_m);
  return out;
}

FrameMeasurement ImageFrontend::process(const ImageFrame& frame, const PreparedFrame* prepared) {
  auto before = std::make_unique<Snapshot>(save());
  try {
    FrameMeasurement m = processUncommitted(frame, prepared);
    if (const std::string bad = FindInvalidMeasurement(m); !bad.empty())
      throw std::invalid_argument("the front-end's measurement is not valid: " + bad);
    before_last_ = std::move(before);
    return m;
  } catch (...) {
    restore(std::move(*before));
    throw;
  }
}

void ImageFrontend::undoLast() {
  if (!before_last_) throw std::logic_error("ImageFrontend::undoLast: no frame to undo");
  restore(std::move(*before_last_));
  before_last_.reset();
}

FrameMeasurement ImageFrontend::processUncommitted(const ImageFrame& frame, const PreparedFrame* prepared) {
  if (const std::string bad = FindInvalidImageFrame(frame); !bad.empty()) throw std::invalid_argument(bad);
  if (frame.image.cols != camera_.width || frame.image.rows != camera_.height)
    throw std::invalid_argument("frame " + std::to_string(frame.frame_index) + ": image is " +
                                std::to_string(frame.image.cols) + "x" + std::to_string(frame.image.rows) +
                                " but the camera calibration is " + std::to_string(camera_.width) + "x" +
                                std::to_string(camera_.height));
  if (prev_frame_index_ && frame.frame_index <= *prev_frame_index_)
    throw std::invalid_argument("frame " + std::to_string(frame.frame_index) + " arrived after frame " +
                                std::to_string(*prev_frame_index_) + ": frames must come in increasing order");
  if (prev_frame_index_ && params_.flow.method == FlowMethod::kPrecomputed && prev_flow_to_next_.empty())
    throw std::invalid_argument("frame " + std::to_string(frame.frame_index) +
                                ": flow method 'precomputed' but the previous frame came without a flow field");

  FrontendFrameStats stats;
  PhaseClock phase;
  std::optional<PreparedFrame> made_here;
  if (!prepared) prepared = &made_here.emplace(Prepare(params_, frame));
  const GreyPyramid& grey = prepared->grey;
  const cv::Mat& gray = grey.gray;
  const cv::Mat& labels = prepared->labels;
  const std::map<int, int>& label_areas = prepared->label_areas;
  const std::map<int, cv::Rect>& label_boxes = prepared->label_boxes;
  const cv::Mat& near_edge = prepared->near_edge;
  const cv::Mat& depth = frame.depth_m;
  for (const auto& [label, area] : label_areas) stats.mask_labels.push_back(label);
  stats.phase_ms.prepare_ms = phase.lap();

  // 1. Flow.
  std::vector<Track> moved;
  std::vector<int> moved_label;
  if (prev_frame_index_ && !tracks_.empty()) {
    std::vector<cv::Point2f> prev_px;
    prev_px.reserve(tracks_.size());
    for (const Track& t : tracks_) {
      prev_px.push_back(t.px);
      if (t.object_id != 0) ++stats.object_counts[t.object_id].previous;
    }
    std::optional<SE3> camera_motion =
        frame.odometry ? std::optional<SE3>(frame.odometry->T_prev_curr) : last_camera_motion_;
    PixelPrediction prediction = predictPixels(camera_motion, label_boxes);
    stats.phase_ms.prepare_ms += phase.lap();
    FlowResult flow = flow_.track(prev_grey_, grey, prev_px, prev_flow_to_next_, prediction.px);
    stats.phase_ms.flow_ms = phase.lap();
    // The searches for object tracks below (Lucas-Kanade's) start from where the camera's and the
    // object's motions put them. The static tracks just found give the camera's motion more exactly than
    // odometry or the last frame's (rendered 0005's odometry is 0.1 to 0.2 m off per frame: 10 to 20 px
    // at a car passing 8 m away), so the predictions are made again from it.
    if (params_.flow.method == FlowMethod::kLucasKanade) {
      if (const auto refined = cameraMotionFromStaticFlow(flow, labels, frame.odometry, camera_motion)) {
        camera_motion = refined;
        prediction = predictPixels(camera_motion, label_boxes);
      }
    }
    resolveStillHypothesis(grey, prev_px, prediction, &flow, &stats.ambiguous);
    retryNearPrediction(grey, prev_px, prediction, &flow);
    stats.phase_ms.refine_ms = phase.lap();
    reacquireWarped(grey, camera_motion, &flow, &stats);
    stats.phase_ms.warped_ms = phase.lap();
    std::vector<float> fb;
    for (size_t i = 0; i < tracks_.size(); ++i) {
      // A point that its box takes out of view is gone: on a repetitive texture the flow search still
      // finds a consistent match near its old position, which reads as a phantom motion (a parked car
      // at the image border "moving" with the camera). Tracks of a known motion are checked the same
      // way once the camera's motion is known (step 4b).
      if (!flow.ok[i] || prediction.leaves_view[i]) {
        stats.left_view += flow.ok[i] && prediction.leaves_view[i];
        continue;
      }
      Track t = tracks_[i];
      t.px = flow.points[i];
      moved.push_back(t);
      moved_label.push_back(LabelAt(labels, t.px));
      fb.push_back(flow.fb_error_px[i]);
    }
    stats.median_fb_error_px = Median(fb);
  }

  // 2. Association of labels with objects, by the labels the object tracks landed in.
  std::map<int, std::map<int, int>> votes;
  std::map<int, int> tracked_per_object;
  for (size_t i = 0; i < moved.size(); ++i) {
    if (moved[i].object_id == 0) continue;
    ++tracked_per_object[moved[i].object_id];
    ++stats.object_counts[moved[i].object_id].flowed;
    if (moved_label[i] > 0) ++votes[moved_label[i]][moved[i].object_id];
  }
  const std::map<int, int> object_of_label = associator_.associate(label_areas, votes, tracked_per_object);
  std::map<int, double> mask_area_frac;  // object id -> share of the image its mask covers
  std::map<int, cv::Rect> object_box;    // object id -> the box around its labels
  for (const auto& [label, object_id] : object_of_label) {
    mask_area_frac[object_id] += static_cast<double>(label_areas.at(label)) / static_cast<double>(labels.total());
    if (const auto box = label_boxes.find(label); box != label_boxes.end()) object_box[object_id] |= box->second;
  }

  // 3. Keep tracks whose pixel still belongs to what they belong to, with depth in range.
  std::vector<Track> kept;           // current pixel; p_camera still at the previous frame
  std::vector<Vec3> p_curr_camera;
  for (size_t i = 0; i < moved.size(); ++i) {
    const Track& t = moved[i];
    if (near_edge.at<uint8_t>(cvRound(t.px.y), cvRound(t.px.x))) continue;
    const float z = DepthAt(depth, t.px);
    if (t.object_id == 0) {
      if (moved_label[i] != 0 || z < params_.static_min_depth_m || z > params_.static_max_depth_m) continue;
    } else {
      const auto owner = object_of_label.find(moved_label[i]);
      if (owner == object_of_label.end() || owner->second != t.object_id || z < params_.static_min_depth_m) continue;
    }
    kept.push_back(t);
    p_curr_camera.push_back(camera_.backProject(t.px.x, t.px.y, z));
  }

  stats.phase_ms.keep_ms = phase.lap();

  // 4a. Camera motion from the static tracks; drop their outliers.
  std::vector<Vec3> static_prev;
  std::vector<Vec2> static_uv;
  std::vector<size_t> static_index;
  for (size_t i = 0; i < kept.size(); ++i) {
    if (kept[i].object_id != 0) continue;
    static_prev.push_back(kept[i].p_camera);
    static_uv.emplace_back(kept[i].px.x, kept[i].px.y);
    static_index.push_back(i);
  }
  std::vector<uint8_t> keep(kept.size(), 1);
  std::optional<SE3> T_prev_curr;
  bool odometry_rejected = false;
  if (frame.odometry) T_prev_curr = frame.odometry->T_prev_curr;
  // Frames were dropped since the previous one (serve when it falls behind): the flow spans several frames.
  const bool after_gap =
      prev_frame_index_ && StepPeriods(prev_t_ns_, frame.t_ns, params_.frame_interval_s) > kGapPeriods;
  if (const auto pnp = EstimateCameraMotionPnp(static_prev, static_uv, camera_, params_.pnp, T_prev_curr)) {
    stats.pnp_inliers = static_cast<int>(pnp->inliers.size());
    stats.camera_from_pnp = true;
    for (size_t j : static_index) keep[j] = 0;
    for (int j : pnp->inliers) keep[static_index[j]] = 1;
    // Odometry that contradicts a well-supported visual motion is not fused here, and not handed to the
    // back-end as a factor.
    T_prev_curr = FuseUnlessContradicted(*pnp, frame.odometry, params_.odometry_gate_chi2, &odometry_rejected);
    // After dropped frames (serve when it falls behind) the flow spans several frames' motion, where a
    // textured scene's look-alikes can give a well-supported but wrong PnP: the odometry composed over the
    // gap is kept then, with the static points that agree with it.
    if (odometry_rejected && after_gap) {
      odometry_rejected = false;
      T_prev_curr = frame.odometry->T_prev_curr;
      const SE3 T_curr_prev = T_prev_curr->inverse();
      for (size_t j = 0; j < static_index.size(); ++j) {
        const Vec3 p = T_curr_prev * static_prev[j];
        keep[static_index[j]] = p.z() > 0.1 && (camera_.project(p) - static_uv[j]).norm() <= params_.pnp.reprojection_px;
      }
    }
    stats.odometry_rejected = odometry_rejected;
  } else if (frame.odometry && after_gap) {
    // No visual consensus across a gap, where the flow's matches are mostly look-alikes: the odometry is
    // the motion, and no static track goes on to the back-end, where unverified ones pull the camera off
    // it (28 held a rendered city's camera 10 m behind its odometry after 18 dropped frames). Checking
    // them against the odometry is not enough: a look-alike on another surface can sit at the right pixel
    // with the wrong depth (one such point held the camera 1.7 m off). Without a gap they go on: the flow
    // of one frame is right, and PnP fails there for other reasons (rendered 0000 stereo, one frame of 154:
    // dropping its 273 tracks doubled the ATE).
    for (size_t j : static_index) keep[j] = 0;
  }

  stats.phase_ms.pnp_ms = phase.lap();

  // 4b. Each object's motion (in the previous camera frame) by 3D-3D RANSAC; drop its outliers.
  std::map<int, std::vector<size_t>> object_tracks;
  for (size_t i = 0; i < kept.size(); ++i)
    if (kept[i].object_id != 0) object_tracks[kept[i].object_id].push_back(i);
  const SE3 T_prev_curr_or_identity = T_prev_curr.value_or(SE3());
  std::map<int, ObjectMotionFit> fits;
  for (auto& [object_id, indices] : object_tracks) {
    if (T_prev_curr) {
      for (size_t i : indices) keep[i] = 0;  // those that stay are decided by the fit below
      dropLeavingTracks(object_id, *T_prev_curr, kept, &indices, &stats.left_view);
    }
    std::vector<Vec3> src, dst;
    for (size_t i : indices) {
      src.push_back(kept[i].p_camera);
      dst.push_back(T_prev_curr_or_identity * p_curr_camera[i]);
    }
    auto fit = AlignRigidRansac(src, dst, params_.object_ransac);
    if (fit && !acceptObjectMotion(object_id, fit->transform, src, fit->is_inlier, frame.frame_index)) {
      fit.reset();
      stats.object_counts[object_id].motion_rejected = true;
    }
    for (size_t n = 0; n < indices.size(); ++n) keep[indices[n]] = fit && fit->is_inlier[n];
    if (fit) fits[object_id] = SummariseMotionFit(fit->transform, src, dst, fit->is_inlier);
  }

  std::vector<Track> tracks;
  for (size_t i = 0; i < kept.size(); ++i) {
    if (!keep[i]) continue;
    Track t = kept[i];
    t.p_camera = p_curr_camera[i];
    tracks.push_back(t);
    (t.object_id == 0 ? stats.static_tracked : stats.object_points_tracked)++;
    if (t.object_id != 0) ++stats.object_counts[t.object_id].tracked;
  }

  stats.phase_ms.objects_ms = phase.lap();

  // 5. New points.
  const size_t before = tracks.size();
  replenish(gray, depth, labels, near_edge, prepared->background_allowed, object_of_label, label_boxes, T_prev_curr,
            &tracks);
  stats.phase_ms.replenish_ms = phase.lap();
  for (size_t i = before; i < tracks.size(); ++i) {
    (tracks[i].object_id == 0 ? stats.static_new : stats.object_points_new)++;
    if (tracks[i].object_id != 0) ++stats.object_counts[tracks[i].object_id].added;
  }

  // The measurement; objects too far or with too few points are left out and their tracks end.
  FrameMeasurement out;
  out.frame_index = frame.frame_index;
  out.t_ns = frame.t_ns;
  if (prev_frame_index_) {
    if (!odometry_rejected) out.odometry = frame.odometry;
    out.camera_motion_guess = T_prev_curr;
  }
  std::map<int, ObjectObservation> objects;
  for (const Track& t : tracks) {
    if (t.object_id == 0)
      out.static_points.push_back({t.id, t.p_camera});
    else
      objects[t.object_id].points.push_back({t.id, t.p_camera});
  }
  std::set<int> measured;
  for (auto& [object_id, obs] : objects) {
    Vec3 centroid = Vec3::Zero();
    for (const auto& p : obs.points) centroid += p.p_camera;
    centroid /= static_cast<double>(obs.points.size());
    if (static_cast<int>(obs.points.size()) < params_.min_points_per_object ||
        centroid.norm() > params_.object_max_distance_m)
      continue;
    obs.object_id = object_id;
    if (const auto fit = fits.find(object_id); fit != fits.end()) obs.motion_fit = fit->second;
    if (const auto area = mask_area_frac.find(object_id); area != mask_area_frac.end()) obs.mask_area_frac = area->second;
    if (const auto box = object_box.find(object_id); box != object_box.end())
      obs.image_box = ImageBox{box->second.x, box->second.y, box->second.width, box->second.height};
    measured.insert(object_id);
    stats.object_counts[object_id].measured = true;
    out.objects.push_back(std::move(obs));
  }
  tracks.erase(std::remove_if(tracks.begin(), tracks.end(),
                              [&](const Track& t) { return t.object_id != 0 && !measured.count(t.object_id); }),
               tracks.end());
  stats.objects = static_cast<int>(out.objects.size());

  tracks_ = std::move(tracks);
  prev_label_boxes_ = label_boxes;
  last_camera_motion_ = T_prev_curr;
  for (auto it = last_object_motion_.begin(); it != last_object_motion_.end();)
    it = frame.frame_index - it->second.frame_index > kObjectMotionMemoryFrames ? last_object_motion_.erase(it) : ++it;
  prev_grey_ = grey;
  prev_depth_ = depth;
  prev_flow_to_next_ = frame.flow_to_next;
  prev_frame_index_ = frame.frame_index;
  prev_t_ns_ = frame.t_ns;
  stats.phase_ms.measurement_ms = phase.lap();
  stats_ = stats;
  return out;
}

std::optional<bool> ImageFrontend::withinAccelerationBound(int object_id, const SE3& motion,
                                                           const std::vector<Vec3>& p_prev,
                                                           const std::vector<bool>& inlier) const {
  const auto last = last_object_motion_.find(object_id);
  if (last == last_object_motion_.end()) return std::nullopt;
  Vec3 centroid = Vec3::Zero();
  int n = 0;
  for (size_t i = 0; i < p_prev.size(); ++i)
    if (inlier[i]) centroid += p_prev[i], ++n;
  if (n == 0) return false;
  centroid /= n;
  const double dt = params_.frame_interval_s;
  // The motion may have changed for as many frames as passed since it was fitted, less those whose fit it
  // rejected: a fit judged wrong is no sign that the motion changed, and counting it let the next wrong
  // fit through (a half-hidden van on rendered 0000, its tracks stuck to the edge of a cyclist in front).
  const int frames_since =
      std::max(1, *prev_frame_index_ + 1 - last->second.frame_index - last->second.rejections);
  const double change_m = ((motion * centroid) - (last->second.motion * centroid)).norm();
  return change_m <= params_.object_max_acceleration_mps2 * dt * dt * frames_since;
}

bool ImageFrontend::acceptObjectMotion(int object_id, const SE3& motion, const std::vector<Vec3>& p_prev,
                                       const std::vector<bool>& inlier, int frame_index) {
  constexpr int kMaxRejections = 3;
  const std::optional<bool> within = withinAccelerationBound(object_id, motion, p_prev, inlier);
  auto memory = last_object_motion_.find(object_id);
  if (within == false && memory->second.confirmations >= kConfirmedFits) {
    if (++memory->second.rejections >= kMaxRejections) last_object_motion_.erase(memory);
    return false;
  }
  const int confirmations = within.value_or(false) ? memory->second.confirmations + 1 : 1;
  last_object_motion_[object_id] = {motion, frame_index, confirmations, 0};
  return true;
}

ImageFrontend::PixelPrediction ImageFrontend::predictPixels(const std::optional<SE3>& camera,
                                                           const std::map<int, cv::Rect>& label_boxes) const {
  const SE3 T_curr_prev = camera.value_or(SE3()).inverse();
  PixelPrediction prediction;
  prediction.px.reserve(tracks_.size());
  prediction.leaves_view.reserve(tracks_.size());
  for (const Track& t : tracks_) {
    Vec3 p = t.p_camera;  // previous camera frame
    if (t.object_id != 0) {
      if (const auto m = last_object_motion_.find(t.object_id); m != last_object_motion_.end()) {
        p = m->second.motion * p;
      } else if (params_.association.mask_ids_tracked) {
        const auto before = prev_label_boxes_.find(t.object_id), now = label_boxes.find(t.object_id);
        if (before != prev_label_boxes_.end() && now != label_boxes.end()) {
          const cv::Point2f px = PredictFromMaskBoxes(before->second, now->second, t.px, camera_.width, camera_.height);
          const bool inside = inView(px.x, px.y);
          if (camera && inside) {
            const Vec3 still = T_curr_prev * p;
            const Vec2 uv = still.z() > 0.1 ? camera_.project(still) : Vec2(-1.0, -1.0);
            prediction.from_box.push_back(prediction.px.size());
            prediction.px_if_still.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
          }
          prediction.px.push_back(inside ? px : t.px);
          prediction.leaves_view.push_back(!inside);
          continue;
        }
      }
    }
    p = T_curr_prev * p;
    const Vec2 uv = p.z() > 0.1 ? camera_.project(p) : Vec2(t.px.x, t.px.y);
    const bool inside = inView(uv.x(), uv.y());
    prediction.px.push_back(inside ? cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y())) : t.px);
    prediction.leaves_view.push_back(0);
  }
  if (params_.flow.method != FlowMethod::kLucasKanade) {  // the dense methods and matching need no start
    prediction.px.clear();
    prediction.from_box.clear();
    prediction.px_if_still.clear();
  }
  return prediction;
}

std::optional<SE3> ImageFrontend::cameraMotionFromStaticFlow(const FlowResult& flow, const cv::Mat& labels,
                                                             const std::optional<OdometryMeasurement>& odometry,
                                                             const std::optional<SE3>& guess) const {
  std::vector<Vec3> p_prev;
  std::vector<Vec2> uv;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    if (tracks_[i].object_id != 0 || !flow.ok[i] || !inView(flow.points[i].x, flow.points[i].y) ||
        LabelAt(labels, flow.points[i]) != 0)
      continue;
    p_prev.push_back(tracks_[i].p_camera);
    uv.emplace_back(flow.points[i].x, flow.points[i].y);
  }
  const auto pnp = EstimateCameraMotionPnp(p_prev, uv, camera_, params_.pnp, guess);
  if (!pnp) return std::nullopt;
  bool odometry_rejected = false;
  return FuseUnlessContradicted(*pnp, odometry, params_.odometry_gate_chi2, &odometry_rejected);
}

bool ImageFrontend::inView(double u, double v) const {
  return u >= 0 && v >= 0 && u <= camera_.width - 1 && v <= camera_.height - 1;
}

const ImageFrontend::ObjectMotionMemory* ImageFrontend::confirmedMotion(int object_id) const {
  const auto memory = last_object_motion_.find(object_id);
  return memory != last_object_motion_.end() && memory->second.confirmations >= kConfirmedFits ? &memory->second
                                                                                               : nullptr;
}

void ImageFrontend::retryNearPrediction(const GreyPyramid& grey, const std::vector<cv::Point2f>& prev_px,
                                        const PixelPrediction& prediction, FlowResult* flow) const {
  if (params_.flow.method != FlowMethod::kLucasKanade || prediction.px.empty()) return;
  // Only where the full pyramid's coarsest window reaches past the image border: elsewhere a track the
  // flow lost was lost for a reason (an occlusion, a look-alike the prediction is closer to than the
  // point), and on rendered 0005's passing cars retrying those made the speeds worse (OMSE 0.26 -> 0.60 %).
  const float reach = 0.5f * static_cast<float>(params_.flow.lk_window_px) * static_cast<float>(1 << params_.flow.lk_pyramid_levels);
  const auto near_border = [&](const cv::Point2f& px) {
    return px.x < reach || px.y < reach || px.x > camera_.width - 1 - reach || px.y > camera_.height - 1 - reach;
  };
  std::vector<cv::Point2f> from, start;
  std::vector<size_t> index;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    if (flow->ok[i] || prediction.leaves_view[i] || tracks_[i].object_id == 0 || !confirmedMotion(tracks_[i].object_id))
      continue;
    if (prediction.px[i] == prev_px[i] || !near_border(prediction.px[i])) continue;
    from.push_back(prev_px[i]);
    start.push_back(prediction.px[i]);
    index.push_back(i);
  }
  if (index.empty()) return;
  const FlowResult near = flow_.trackNearPrediction(prev_grey_, grey, from, start);
  for (size_t j = 0; j < index.size(); ++j) {
    if (!near.ok[j]) continue;
    flow->ok[index[j]] = 1;
    flow->points[index[j]] = near.points[j];
    flow->fb_error_px[index[j]] = near.fb_error_px[j];
  }
}

void ImageFrontend::reacquireWarped(const GreyPyramid& grey, const std::optional<SE3>& camera_motion, FlowResult* flow,
                                    FrontendFrameStats* stats) const {
  if (params_.flow.method != FlowMethod::kLucasKanade || params_.warped_search.radius_px == 0 || !camera_motion ||
      prev_depth_.empty())
    return;
  // Neighbours this far from a point give the local map; one deeper or shallower by more than the
  // jump is across an edge, and the point's own depth stands in for it (a fronto-parallel patch).
  constexpr float kStepPx = 3.0f;
  constexpr double kDepthJumpM = 0.5;
  const SE3 T_curr_prev = camera_motion->inverse();
  std::vector<WarpedPatchRequest> requests;
  std::vector<size_t> index;
  std::vector<float> deformations;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    const Track& t = tracks_[i];
    if (t.object_id == 0) continue;
    const ObjectMotionMemory* memory = confirmedMotion(t.object_id);
    if (!memory) continue;
    const SE3 T_curr_prev_object = T_curr_prev * memory->motion;
    bool valid = true;
    const auto predict = [&](const Vec3& p_prev) {
      const Vec3 p = T_curr_prev_object * p_prev;
      if (!(p.z() > 0.1)) valid = false;
      const Vec2 uv = camera_.project(p);
      return cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    };
    const auto neighbour = [&](float du, float dv) {
      const cv::Point2f px(t.px.x + du, t.px.y + dv);
      const float z = DepthAt(prev_depth_, px);
      const double depth = z > 0.0f && std::abs(z - t.p_camera.z()) < kDepthJumpM ? z : t.p_camera.z();
      return predict(camera_.backProject(px.x, px.y, depth));
    };
    const cv::Point2f px = predict(t.p_camera);
    if (!valid || !inView(px.x, px.y)) continue;
    const cv::Point2f du = (neighbour(kStepPx, 0) - neighbour(-kStepPx, 0)) / (2.0f * kStepPx);
    const cv::Point2f dv = (neighbour(0, kStepPx) - neighbour(0, -kStepPx)) / (2.0f * kStepPx);
    // The flow models a neighbourhood that keeps its shape: where it lost such a track it was for another
    // reason (an occlusion, a contour), and matches found for those made the speeds worse, not better.
    // Where the patch deforms, the search decides even if the flow found a match: that match may be a
    // look-alike the flow slid onto (rendered 0005: on the pairs estimated either way, the speed error
    // fell from 0.31 to 0.28 %).
    const float deformation = std::max({std::abs(du.x - 1.0f), std::abs(dv.y - 1.0f), std::abs(du.y), std::abs(dv.x)});
    if (!valid || deformation < params_.warped_search.min_deformation) continue;
    requests.push_back({t.px, px, cv::Matx22f(du.x, dv.x, du.y, dv.y)});
    index.push_back(i);
    deformations.push_back(deformation);
  }
  if (requests.empty()) return;
  const std::vector<WarpedPatchMatch> found = SearchWarpedPatches(prev_grey_.gray, grey.gray, requests, params_.warped_search);
  for (size_t j = 0; j < found.size(); ++j) {
    if (!found[j].ok) {
      if (deformations[j] >= params_.warped_search.max_flow_deformation) flow->ok[index[j]] = 0;
      continue;
    }
    const size_t i = index[j];
    flow->ok[i] = 1;
    flow->points[i] = found[j].px;
    flow->fb_error_px[i] = 0.0f;  // no backward pass: the match's strength and uniqueness stand for it
    ++stats->object_counts[tracks_[i].object_id].reacquired;
  }
}

void ImageFrontend::dropLeavingTracks(int object_id, const SE3& T_prev_curr, const std::vector<Track>& kept,
                                      std::vector<size_t>* indices, int* left_view) const {
  const auto memory = last_object_motion_.find(object_id);
  if (memory == last_object_motion_.end()) return;
  const SE3 T_curr_prev = T_prev_curr.inverse();
  const auto leaves = [&](size_t i) { return leavesView(memory->second.motion, T_curr_prev, kept[i].p_camera); };
  const size_t before = indices->size();
  indices->erase(std::remove_if(indices->begin(), indices->end(), leaves), indices->end());
  *left_view += static_cast<int>(before - indices->size());
}

bool ImageFrontend::leavesView(const SE3& object_motion, const SE3& T_curr_prev, const Vec3& p_prev_camera) const {
  const Vec3 p = T_curr_prev * (object_motion * p_prev_camera);
  const Vec2 uv = camera_.project(p);
  return !(p.z() > 0.1 && inView(uv.x(), uv.y()));
}

void ImageFrontend::resolveStillHypothesis(const GreyPyramid& grey, const std::vector<cv::Point2f>& prev_px,
                                           const PixelPrediction& prediction, FlowResult* flow, int* ambiguous) {
  // A still start is confirmed when the flow stays within this of it (a still object's prediction is
  // exact up to the depth noise); two matches closer than this are the same.
  constexpr float kSamePx = 2.0f;
  // The box start is rough (the box is that of the visible part), but a match farther from it than half
  // the predicted move is a track that went back where it was: held by an occluding edge or by the
  // image border.
  constexpr float kBoxSlackPx = 4.0f;
  for (size_t i : prediction.from_box) {
    const float predicted_move = static_cast<float>(cv::norm(prediction.px[i] - prev_px[i]));
    if (flow->ok[i] && cv::norm(flow->points[i] - prediction.px[i]) > 0.5f * predicted_move + kBoxSlackPx) {
      flow->ok[i] = 0;
      ++*ambiguous;
    }
  }
  std::vector<cv::Point2f> starts, still_px;
  std::vector<size_t> index;
  for (size_t j = 0; j < prediction.from_box.size(); ++j) {
    const cv::Point2f& uv = prediction.px_if_still[j];
    if (!inView(uv.x, uv.y)) {
      // Still, it would have left the view; moving as its box does, it stays: unknown, and a match
      // found inside may be the wrong one (an image-border strip of a parked car).
      *ambiguous += flow->ok[prediction.from_box[j]];
      flow->ok[prediction.from_box[j]] = 0;
      continue;
    }
    starts.push_back(prev_px[prediction.from_box[j]]);
    still_px.push_back(uv);
    index.push_back(prediction.from_box[j]);
  }
  if (index.empty()) return;
  const FlowResult still = flow_.track(prev_grey_, grey, starts, cv::Mat(), still_px);
  for (size_t j = 0; j < index.size(); ++j) {
    if (!still.ok[j] || cv::norm(still.points[j] - still_px[j]) > kSamePx) continue;  // not still
    const size_t i = index[j];
    if (flow->ok[i] && cv::norm(flow->points[i] - still.points[j]) > kSamePx) {
      flow->ok[i] = 0;
      ++*ambiguous;
      continue;
    }
    flow->ok[i] = 1;
    flow->points[i] = still.points[j];
    flow->fb_error_px[i] = still.fb_error_px[j];
  }
}

void ImageFrontend::replenish(const cv::Mat& gray, const cv::Mat& depth, const cv::Mat& labels,
                              const cv::Mat& near_edge, const cv::Mat& background,
                              const std::map<int, int>& object_of_label,
                              const std::map<int, cv::Rect>& label_boxes, const std::optional<SE3>& T_prev_curr,
                              std::vector<Track>* tracks) {
  std::vector<cv::Point2f> existing;
  for (const Track& t : *tracks)
    if (t.object_id == 0) existing.push_back(t.px);
  const auto point_at = [&](const cv::Point2f& px) { return camera_.backProject(px.x, px.y, DepthAt(depth, px)); };
  for (const cv::Point2f& px : DetectOnGrid(gray, background, existing, params_.static_grid))
    tracks->push_back({next_track_id_++, 0, px, point_at(px)});

  // The next frame's camera motion is taken to repeat this one's (as the next prediction does).
  const std::optional<SE3> T_next_curr = T_prev_curr ? std::optional<SE3>(T_prev_curr->inverse()) : std::nullopt;
  for (const auto& [label, object_id] : object_of_label) {
    const ObjectMotionMemory* memory = T_next_curr ? confirmedMotion(object_id) : nullptr;
    const auto leaves_next = [&](const Vec3& p) { return memory && leavesView(memory->motion, *T_next_curr, p); };
    int staying = 0;
    for (const Track& t : *tracks) staying += t.object_id == object_id && !leaves_next(t.p_camera);
    const int missing = params_.max_points_per_object - staying;
    if (missing <= 0) continue;
    const cv::Rect box = label_boxes.at(label);
    const cv::Mat inside = NewPointMask(labels, depth, near_edge, box, label, params_.static_min_depth_m,
                                        std::numeric_limits<double>::infinity());
    std::vector<cv::Point2f> here;
    for (const Track& t : *tracks)
      if (t.object_id == object_id) here.push_back(t.px);
    const cv::Point2f offset(static_cast<float>(box.x), static_cast<float>(box.y));
    std::vector<cv::Point2f> found = DetectOnGrid(gray(box), inside, {}, params_.object_grid);
    if (static_cast<int>(found.size()) < missing)
      for (const auto& p : SampleLattice(inside, cv::Rect(0, 0, box.width, box.height), params_.object_lattice_step_px))
        found.push_back(p);
    for (auto& p : found) p += offset;
    int added = 0;
    for (const cv::Point2f& p : found) {
      if (added >= missing) break;
      bool close = false;
      for (const auto& q : here)
        if (cv::norm(p - q) < params_.object_grid.min_distance_px) { close = true; break; }
      if (close) continue;
      const Vec3 p_camera = point_at(p);
      if (leaves_next(p_camera)) continue;
      here.push_back(p);
      tracks->push_back({next_track_id_++, object_id, p, p_camera});
      ++added;
    }
  }
}

}  // namespace dslam
