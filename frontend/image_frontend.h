#pragma once
// The image front-end (the paper's system overview): instance masks say which points may move,
// optical flow carries points from frame to frame, depth lifts them to 3D. Per frame it
//  1. tracks every live point with the configured flow (forward-backward checked); object tracks that
//     the flow lost or that deform are searched for again from predictions that take the camera's motion
//     from the static tracks just found;
//  2. associates the current mask labels with objects (mask ids, or flow-propagated overlap);
//  3. keeps a static track only on background pixels and an object track only inside its object's mask,
//     both with valid depth in range;
//  4. estimates the camera motion by PnP-RANSAC on the static tracks (fused with odometry when present)
//     and drops the static outliers; fits each object's motion by 3D-3D RANSAC and drops its outliers;
//  5. replenishes background features on a grid and object points inside the masks, not where an
//     object's motion takes them out of view by the next frame;
// and returns the frame's measurement for the back-end. The static/dynamic decision stays with
// DynamicObjectClassifier, which works on these measurements.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "data/measurements.h"
#include "frontend/frontend_params.h"
#include "data/image_frame.h"
#include "geometry/pinhole_camera.h"

namespace dslam {

struct FrontendFrameStats {
  int static_tracked = 0;     // static tracks carried over from the previous frame
  int static_new = 0;
  int object_points_tracked = 0;
  int object_points_new = 0;
  int objects = 0;            // objects in the measurement
  int pnp_inliers = 0;        // 0 when PnP failed or did not run
  bool camera_from_pnp = false;
  bool odometry_rejected = false;  // the odometry contradicted the PnP motion (frontend.odometry_gate_chi2)
  double median_fb_error_px = 0.0;  // over the points the flow kept
  int left_view = 0;  // object tracks ended because their predicted motion took them out of the image
  int ambiguous = 0;  // object tracks ended because a still and a moving start both matched (see ImageFrontend)
  std::vector<int> mask_labels;     // instance labels at least min_mask_area_pct of the image
  struct ObjectCounts {
    int previous = 0;  // its tracks at the end of the previous frame: the tracks that could survive
    int flowed = 0;   // points the flow carried into this frame (forward-backward consistent, or re-found)
    int reacquired = 0;  // of those, points the warped search placed (the flow lost them, or it corrected them)
    int tracked = 0;  // points carried over from the previous frame (after the mask, depth and RANSAC checks)
    int added = 0;    // new points
    bool measured = false;  // in the measurement (enough points, within range)
    bool motion_rejected = false;  // its motion fit broke the acceleration bound
  };
  std::map<int, ObjectCounts> object_counts;  // by object id
  // Where the frame's time went, ms (steady clock): grey image, labels and mask edges; the flow search;
  // the searches that refine it (camera motion from static flow, still starts, retries near the
  // prediction); the warped-patch reacquisition; keeping tracks (association, mask and depth checks);
  // the camera's PnP; the objects' RANSAC; new points; the measurement.
  struct PhaseTimes {
    double prepare_ms = 0, flow_ms = 0, refine_ms = 0, warped_ms = 0, keep_ms = 0, pnp_ms = 0, objects_ms = 0,
           replenish_ms = 0, measurement_ms = 0;
  };
  PhaseTimes phase_ms;
};

// What the front-end takes from a frame alone, before any tracking: its grey image and pyramid, its mask
// labels (CV_32SC1) with the areas of those large enough to be objects and every label's box, the pixels
// near a mask edge and where a new static point may go. ImageFrontend::Prepare makes it on any thread, so
// that a pipeline can prepare frame k+1 while the front-end tracks frame k.
struct PreparedFrame {
  GreyPyramid grey;
  cv::Mat labels;
  std::map<int, int> label_areas;       // labels at least min_mask_area_pct of the image
  std::map<int, cv::Rect> label_boxes;  // every label's box
  cv::Mat near_edge;                    // CV_8UC1, non-zero within mask_border_px of a mask edge
  cv::Mat background_allowed;           // CV_8UC1, non-zero where a new static point may go (no label, no
                                        // mask edge, depth within the static range)
};

class ImageFrontend {
 public:
  // Throws std::invalid_argument naming what is wrong with a frame that cannot be prepared (FindInvalidImageFrame).
  static PreparedFrame Prepare(const FrontendParams& params, const ImageFrame& frame);

  ImageFrontend(const FrontendParams& params, const PinholeCamera& camera);
  ~ImageFrontend();

  // Throws std::invalid_argument naming what is wrong with the frame (sizes, types, order), or with the
  // measurement it would give (the back-end's own check, data/measurements.h: what the front-end commits
  // the back-end takes); the front-end's state is then unchanged, whatever was thrown, and the next good
  // frame continues from the last good one.
  // `prepared`, when given, is Prepare(params, frame) made elsewhere; the result is the same.
  FrameMeasurement process(const ImageFrame& frame, const PreparedFrame* prepared = nullptr);
  // Takes back the last process() (once): for a caller whose next stage refused its measurement, so that
  // both stages commit a frame together or not at all. Throws std::logic_error when there is nothing to undo.
  void undoLast();

  const FrontendFrameStats& lastStats() const { return stats_; }

 private:
  struct Track {
    int64_t id = 0;
    int object_id = 0;  // 0: static
    cv::Point2f px;
    Vec3 p_camera = Vec3::Zero();
  };

  // New background features on a grid and object points inside the masks, up to each object's cap. A
  // point that an object's confirmed motion and the camera's motion T_prev_curr, repeated, take out of
  // the image by the next frame can give no pair there: it does not count towards the cap and is not
  // added, so a car leaving the view, its front first, gets points on the side that stays. `background`:
  // PreparedFrame::background_allowed.
  void replenish(const cv::Mat& gray, const cv::Mat& depth, const cv::Mat& labels, const cv::Mat& near_edge,
                 const cv::Mat& background, const std::map<int, int>& object_of_label,
                 const std::map<int, cv::Rect>& label_boxes, const std::optional<SE3>& T_prev_curr,
                 std::vector<Track>* tracks);

  FrontendParams params_;
  PinholeCamera camera_;
  FlowTracker flow_;
  ObjectAssociator associator_;

  // Whether `motion` of the object's inlier points p_prev (previous camera frame) stays within the
  // acceleration bound of its last known motion; nullopt when there is none to compare with.
  std::optional<bool> withinAccelerationBound(int object_id, const SE3& motion, const std::vector<Vec3>& p_prev,
                                              const std::vector<bool>& inlier) const;
  // The acceleration gate: a fit is rejected only against a motion confirmed by consecutive consistent
  // fits (a first fit from a few points may itself be the wrong one), and a memory that keeps rejecting
  // is dropped (the object really changed its motion, or the memory was wrong).
  bool acceptObjectMotion(int object_id, const SE3& motion, const std::vector<Vec3>& p_prev,
                          const std::vector<bool>& inlier, int frame_index);
  // Where the motion model expects each track in the new frame (constant velocity for the camera and
  // for each object), to start the flow search there. An object without a known motion (new, or back
  // after an occlusion) is predicted from its mask's bounding box in both frames when the segmenter's
  // ids are tracked: a car coming the other way grows and moves too fast for flow started from the old
  // position.
  // An object's tracks predicted from its box are also searched from where they would be if the object
  // stood still (the camera's motion alone): see resolveStillHypothesis.
  struct PixelPrediction {
    std::vector<cv::Point2f> px;       // one per track (LK only; empty for the dense methods)
    std::vector<uint8_t> leaves_view;  // one per track: its object's box takes it out of the image
    std::vector<size_t> from_box;      // tracks predicted from their object's box (LK only)
    std::vector<cv::Point2f> px_if_still;  // one per from_box entry
  };
  // Removes from `indices` (into `kept`) the tracks of an object that its last known motion and the
  // camera's motion take out of the image: a match found for them is a wrong one.
  void dropLeavingTracks(int object_id, const SE3& T_prev_curr, const std::vector<Track>& kept,
                         std::vector<size_t>* indices, int* left_view) const;
  // Whether an object motion (in the earlier camera's frame), then the camera's motion T_curr_prev, take a
  // point of the earlier camera frame out of the later image.
  bool leavesView(const SE3& object_motion, const SE3& T_curr_prev, const Vec3& p_prev_camera) const;
  // Checks of a box-predicted track, whose object's motion is unknown. A parked car passing the image
  // border, or sliding behind a car that moves with us, has tracks that the flow drags onto a wrong but
  // forward-backward consistent match near their old pixel. So: a match farther from the box start
  // than half the box's move ends the track; the flow also starts from where the point would be if the
  // object stood still, and a match that stays there is taken; when both starts give consistent but
  // different matches, or standing still would have taken the point out of view, the track ends.
  // Ended tracks are counted in `ambiguous`.
  void resolveStillHypothesis(const GreyPyramid& grey, const std::vector<cv::Point2f>& prev_px,
                              const PixelPrediction& prediction, FlowResult* flow, int* ambiguous);
  PixelPrediction predictPixels(const std::optional<SE3>& camera_motion,
                                const std::map<int, cv::Rect>& label_boxes) const;
  // The camera's motion from the static tracks the flow found (PnP-RANSAC, fused with odometry that agrees
  // with it); nullopt with too few.
  std::optional<SE3> cameraMotionFromStaticFlow(const FlowResult& flow, const cv::Mat& labels,
                                                const std::optional<OdometryMeasurement>& odometry,
                                                const std::optional<SE3>& guess) const;
  // Whether a pixel lies in the image (pixel centres 0 .. width - 1); false for a non-finite one.
  bool inView(double u, double v) const;
  struct ObjectMotionMemory;
  // The object's motion memory once two consecutive fits agreed on it (kConfirmedFits); else null.
  const ObjectMotionMemory* confirmedMotion(int object_id) const;
  // Tracks of an object with a confirmed motion that the flow lost, predicted within reach of the
  // coarsest pyramid window from the image border, are searched for again from their predicted pixel
  // with two pyramid levels only (FlowTracker::trackNearPrediction): a car leaving the view at 100 px a
  // frame keeps the tracks of its part still inside.
  void retryNearPrediction(const GreyPyramid& grey, const std::vector<cv::Point2f>& prev_px,
                           const PixelPrediction& prediction, FlowResult* flow) const;
  // Tracks of an object with a confirmed motion, where that motion deforms their patch (a car passing
  // close by shows a side that stretches and shears from frame to frame), are searched for around their
  // predicted pixel with their previous patch warped by the motion (SearchWarpedPatches). A match found
  // replaces the flow's, or takes the place of a track the flow lost; where the patch deforms beyond
  // what the flow can follow (WarpedSearchParams::max_flow_deformation) and the search finds nothing,
  // the flow's match is dropped too.
  void reacquireWarped(const GreyPyramid& grey, const std::optional<SE3>& camera_motion, FlowResult* flow,
                       FrontendFrameStats* stats) const;

  FrameMeasurement processUncommitted(const ImageFrame& frame, const PreparedFrame* prepared);

  // Everything process() changes, to restore it.
  struct ObjectMotionMemory {
    SE3 motion;             // between consecutive frames, in the earlier camera frame
    int frame_index = 0;    // when it was last fitted
    int confirmations = 1;  // consecutive fits that agreed with each other
    int rejections = 0;     // consecutive fits it rejected
  };
  struct Snapshot;
  Snapshot save() const;
  void restore(Snapshot&& snapshot);

  std::vector<Track> tracks_;
  std::map<int, cv::Rect> prev_label_boxes_;  // mask label -> bounding box in the previous frame
  std::optional<SE3> last_camera_motion_;       // T_prev_curr of the last transition
  std::map<int, ObjectMotionMemory> last_object_motion_;  // kept a few frames across occlusions
  GreyPyramid prev_grey_;  // the previous frame's grey image and its pyramid
  cv::Mat prev_depth_, prev_flow_to_next_;
  std::optional<int> prev_frame_index_;
  int64_t prev_t_ns_ = 0;  // the previous frame's stamp: a longer step than the frame rate's is a gap
  int64_t next_track_id_ = 1;
  FrontendFrameStats stats_;
  std::unique_ptr<Snapshot> before_last_;  // the state before the last process(), for undoLast()
};

}  // namespace dslam
