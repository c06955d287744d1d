#include "output/trajectory_io.h"

#include "output/whole_file.h"

#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace dslam {
namespace {
WholeFile OpenForWriting(const std::string& path) {
  WholeFile out(path);
  out << std::setprecision(9) << std::fixed;
  return out;
}
}  // namespace

void PutTumLine(std::ostream& out, int64_t t_ns, const SE3& pose) {
  const auto& q = pose.rotation();
  const auto& t = pose.translation();
  out << static_cast<double>(t_ns) * 1e-9 << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' '
      << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
}

void PutKittiLine(std::ostream& out, const SE3& pose) {
  const Mat4 T = pose.matrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) out << T(r, c) << ((r == 2 && c == 3) ? '\n' : ' ');
}

void WriteTumTrajectory(const std::string& path, const std::vector<int64_t>& t_ns, const std::vector<SE3>& poses) {
  if (t_ns.size() != poses.size()) throw std::invalid_argument(path + ": timestamps and poses differ in number");
  WholeFile out = OpenForWriting(path);
  for (size_t i = 0; i < poses.size(); ++i) PutTumLine(out, t_ns[i], poses[i]);
  out.commit();
}

void WriteKittiTrajectory(const std::string& path, const std::vector<SE3>& poses) {
  WholeFile out = OpenForWriting(path);
  for (const auto& pose : poses) PutKittiLine(out, pose);
  out.commit();
}

std::vector<SE3> ReadTumTrajectory(const std::string& path, std::vector<int64_t>* t_ns) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<SE3> poses;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double v[8];
    for (double& x : v)
      if (!(fields >> x)) throw std::runtime_error(path + ":" + std::to_string(line_no) + ": expected 8 numbers");
    poses.emplace_back(Eigen::Quaterniond(v[7], v[4], v[5], v[6]), Vec3(v[1], v[2], v[3]));
    if (t_ns) t_ns->push_back(static_cast<int64_t>(v[0] * 1e9 + 0.5));
  }
  return poses;
}

}  // namespace dslam
