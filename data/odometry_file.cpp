#include "data/odometry_file.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <stdexcept>

#include "data/text_parsing.h"

namespace dslam {

std::map<int, OdometryMeasurement> ReadOdometryFile(const std::string& path) {
  std::ifstream in = OpenText(path);
  std::map<int, OdometryMeasurement> odometry;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto fields = SplitFields(line);
    if (fields.empty() || fields[0][0] == '#') continue;
    if (fields.size() != 14)
      throw std::runtime_error(AtLine(path, line_no, "expected 14 fields (frame, t xyz, q xyzw, 6 sigmas), got " +
                                                         std::to_string(fields.size())));
    const int frame = ParseInt(fields[0], path, line_no, "frame");
    if (frame < 1) throw std::runtime_error(AtLine(path, line_no, "frame must be >= 1 (an increment ends there)"));
    if (!odometry.empty() && frame <= odometry.rbegin()->first)
      throw std::runtime_error(AtLine(path, line_no, "frame " + std::to_string(frame) + " does not come after frame " +
                                                         std::to_string(odometry.rbegin()->first)));
    double v[13];
    static const char* kNames[13] = {"tx", "ty", "tz", "qx", "qy", "qz", "qw", "sigma_tx", "sigma_ty",
                                     "sigma_tz", "sigma_rx", "sigma_ry", "sigma_rz"};
    for (int i = 0; i < 13; ++i) v[i] = ParseDouble(fields[i + 1], path, line_no, kNames[i]);
    const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw std::runtime_error(AtLine(path, line_no, "quaternion is not of unit norm"));
    OdometryMeasurement m;
    m.T_prev_curr = SE3(q, Vec3(v[0], v[1], v[2]));
    for (int i = 0; i < 6; ++i) {
      if (!(v[7 + i] > 0.0)) throw std::runtime_error(AtLine(path, line_no, std::string(kNames[7 + i]) + " must be positive"));
      m.sigma[i] = v[7 + i];
    }
    odometry[frame] = m;
  }
  return odometry;
}

void WriteOdometryFile(const std::string& path, const std::map<int, OdometryMeasurement>& odometry) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "# frame tx ty tz qx qy qz qw sigma_tx sigma_ty sigma_tz sigma_rx sigma_ry sigma_rz (T_prev_curr)\n";
  out << std::setprecision(17);
  for (const auto& [frame, m] : odometry) {
    const auto& q = m.T_prev_curr.rotation();
    const Vec3& t = m.T_prev_curr.translation();
    out << frame << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' '
        << q.w();
    for (int i = 0; i < 6; ++i) out << ' ' << m.sigma[i];
    out << '\n';
  }
  if (!out) throw std::runtime_error("error while writing " + path);
}

}  // namespace dslam
