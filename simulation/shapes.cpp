#include "simulation/shapes.h"

#include <algorithm>
#include <cmath>

namespace dslam {

std::vector<SurfacePoint> SampleEllipsoid(double a, double b, double c, int n) {
  std::vector<SurfacePoint> points;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double y = 1.0 - 2.0 * (i + 0.5) / n;
    const double r = std::sqrt(1.0 - y * y);
    const Vec3 unit(r * std::cos(golden * i), y, r * std::sin(golden * i));
    const Vec3 p(a * unit.x(), b * unit.y(), c * unit.z());
    const Vec3 normal = Vec3(p.x() / (a * a), p.y() / (b * b), p.z() / (c * c)).normalized();
    points.push_back({p, normal});
  }
  return points;
}

std::vector<SurfacePoint> SampleBox(double l, double w, double h, double spacing_m) {
  std::vector<SurfacePoint> points;
  auto cells = [&](double extent) { return std::max(1, static_cast<int>(std::round(extent / spacing_m))); };
  // A face spanned by axes u and v around its centre, with outward normal n.
  auto face = [&](const Vec3& centre, const Vec3& u, double u_len, const Vec3& v, double v_len, const Vec3& n) {
    const int nu = cells(u_len), nv = cells(v_len);
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        const double su = ((i + 0.5) / nu - 0.5) * u_len, sv = ((j + 0.5) / nv - 0.5) * v_len;
        points.push_back({centre + su * u + sv * v, n});
      }
  };
  const Vec3 X = Vec3::UnitX(), Y = Vec3::UnitY(), Z = Vec3::UnitZ();
  const Vec3 mid(0.0, -h / 2.0, 0.0);
  face(mid + X * (l / 2), Y, h, Z, w, X);
  face(mid - X * (l / 2), Y, h, Z, w, -X);
  face(mid + Z * (w / 2), X, l, Y, h, Z);
  face(mid - Z * (w / 2), X, l, Y, h, -Z);
  face(Vec3(0.0, -h, 0.0), X, l, Z, w, -Y);  // roof
  return points;
}

}  // namespace dslam
