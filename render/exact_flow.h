#pragma once
// The exact optical flow of a rendered frame to the next: each pixel's surface point (its depth, its
// object from the instance mask) moved by the camera's and its object's true motion and projected into
// the next frame. A pixel with no surface, whose object is gone in the next frame, that leaves the image
// or is hidden there (the next frame's depth at its pixel is nearer) has unknown flow (kUnknownFlow).
// These are the "ground-truth correspondences" of the front-end study (dslam study).

#include "data/dense_maps.h"
#include "data/scene.h"
#include "render/rgbd_renderer.h"

namespace dslam {

// Frames k and k+1 of `scene`, rendered with `camera`.
FlowField ExactFlow(const Scene& scene, int k, const RgbdFrame& frame_k, const RgbdFrame& frame_next,
                    const CameraIntrinsics& camera);

}  // namespace dslam
