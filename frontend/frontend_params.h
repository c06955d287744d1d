#pragma once
// Parameters of the image front-end: plain structs with defaults and validate(), loaded from the
// `frontend:` section of the YAML configuration.

#include "frontend/camera_motion.h"
#include "frontend/feature_detector.h"
#include "frontend/flow_tracker.h"
#include "frontend/object_association.h"
#include "frontend/warped_patch_search.h"
#include "geometry/rigid_alignment.h"

namespace dslam {

struct FrontendParams {
  FlowParams flow;
  FeatureGridParams static_grid{48, 2, 10, 8.0};  // background features: up to 2 per 48 px cell (~400 a frame)
  FeatureGridParams object_grid{10, 1, 5, 5.0};   // object points: denser
  int object_lattice_step_px = 8;     // fill objects without enough corners from a pixel lattice
  int max_points_per_object = 150;
  int min_points_per_object = 6;      // fewer: the object is not measured in that frame
  double static_min_depth_m = 0.5;
  double static_max_depth_m = 40.0;   // background points farther than this are not used
  double object_max_distance_m = 22.0;  // objects whose point centroid is farther are not measured
  double min_mask_area_pct = 0.05;    // instance masks smaller than this share of the image are ignored
  int mask_border_px = 2;             // points within this of a mask edge are dropped (mixed depth, occlusion)
  AssociationParams association;
  PnpParams pnp;
  // Odometry whose increment is this far from the PnP motion (squared Mahalanobis distance, both
  // uncertainties; chi-square with 6 dof, median about 5 on clean data) is dropped for that frame and
  // counted. 50 is a chance below 1e-8 when both are right: only a fault passes it.
  double odometry_gate_chi2 = 50.0;
  RansacParams object_ransac{100, 0.3, 4, 17};  // per-object 3D-3D RANSAC between consecutive frames
  // An object's fitted motion may differ from its previous one by at most this acceleration (at its
  // points' centroid, in m/s^2 over the frame interval); beyond it, the fit comes from bad tracks (an
  // occluding contour, an ambiguous texture) and the object's tracks restart. The fit is expressed in
  // the moving camera's frame, so the bound also absorbs the camera's own turning: 4 g rejects only
  // fits that are clearly wrong (15 m/s^2 also rejected good fits of oncoming cars on KITTI 0005).
  double object_max_acceleration_mps2 = 40.0;
  // Tracks of an object with a confirmed motion that deforms their neighbourhood are searched for as it
  // would look after that motion (frontend/warped_patch_search.h, ImageFrontend::reacquireWarped).
  WarpedSearchParams warped_search;
  double frame_interval_s = 0.1;  // set from the dataset's frame rate

  void validate() const;
};

}  // namespace dslam
