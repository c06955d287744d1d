#pragma once
// RViz markers of one frame's object estimates (visualization_msgs/MarkerArray on rt/<vehicle>/dslam/markers),
// in the "world" frame: a DELETEALL first (objects gone from view disappear), then per object a sphere at its
// centroid (red when it moves, grey when it stands), for a moving object an arrow along its velocity (its
// length the distance covered in 1 s), and a text above it with its id and speed in km/h. No box: the method
// estimates motions, not object extents.

#include "backend/estimator.h"
#include "visualization_msgs_MarkerArray.h"

namespace dslam {

constexpr int kMarkerDeleteAll = 3, kMarkerArrow = 0, kMarkerSphere = 2, kMarkerText = 9;

visualization_msgs::msg::MarkerArray ObjectMarkers(const FrameEstimate& estimate, double frame_rate_hz);

}  // namespace dslam
