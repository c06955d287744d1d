#pragma once
// Surface samples (point + outward normal, body frame) of the simulated object shapes.

#include <vector>

#include "geometry/se3.h"

namespace dslam {

struct SurfacePoint {
  Vec3 p_body;
  Vec3 normal_body;
};

// Ellipsoid centred at the body origin with semi-axes (a, b, c) along x, y, z; n points spread
// evenly (Fibonacci lattice).
std::vector<SurfacePoint> SampleEllipsoid(double a, double b, double c, int n);

// Box in the KITTI body convention: length l along x, width w along z, height h upwards (-y) from
// the bottom face at y = 0; faces sampled on a grid of the given spacing (bottom face omitted).
std::vector<SurfacePoint> SampleBox(double l, double w, double h, double spacing_m);

}  // namespace dslam
