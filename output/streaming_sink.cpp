#include "output/streaming_sink.h"

#include <filesystem>
#include <iomanip>
#include <stdexcept>

#include "output/text_format.h"

namespace dslam {
namespace {

std::ofstream Open(const std::string& path, const std::string& header, bool fixed) {
  std::ofstream out(path, std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << std::setprecision(9);
  if (fixed) out << std::fixed;
  if (!header.empty()) out << header << '\n';
  return out;
}

void PutTum(std::ostream& out, int64_t t_ns, const SE3& T) {
  const auto& q = T.rotation();
  const auto& t = T.translation();
  out << static_cast<double>(t_ns) * 1e-9 << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' '
      << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
}

}  // namespace

StreamingFileSink::StreamingFileSink(const std::string& dir) : dir_(dir) {}

void StreamingFileSink::open() {
  if (opened_) return;
  opened_ = true;
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw std::runtime_error("cannot create output directory " + dir_ + ": " + ec.message());
  // The same formats (and, for the trajectories, the same number format) as the files written at the end.
  camera_ = Open(dir_ + "/camera_ours.tum", "", true);
  online_ = Open(dir_ + "/camera_ours_online.tum", "", true);
  motions_ = Open(dir_ + "/object_motions.csv", kObjectMotionsHeader, false);
  speeds_ = Open(dir_ + "/object_speeds.csv", kObjectSpeedsHeader, false);
  points_ = Open(dir_ + "/map_points.csv", "frame,object_id,x,y,z", false);
}

void StreamingFileSink::frameStamp(int frame, int64_t t_ns) {
  open();
  stamps_.emplace_back(frame, t_ns);
}

void StreamingFileSink::onlinePose(int64_t t_ns, const SE3& T_world_camera) {
  open();
  PutTum(online_, t_ns, T_world_camera);
  online_.flush();
}

void StreamingFileSink::cameraFinal(int frame, const SE3& T_world_camera) {
  open();
  while (!stamps_.empty() && stamps_.front().first < frame) stamps_.pop_front();
  if (stamps_.empty() || stamps_.front().first != frame)
    throw std::logic_error("streaming sink: no stamp for frame " + std::to_string(frame));
  PutTum(camera_, stamps_.front().second, T_world_camera);
  stamps_.pop_front();
  flush();  // once per frame: each frame added makes at most one camera final
}

void StreamingFileSink::motionFinal(const ObjectMotionEstimate& m) {
  open();
  const auto& t = m.H_world.translation();
  const auto& q = m.H_world.rotation();
  motions_ << m.frame << ',' << m.object_id << ',' << m.is_dynamic << ',' << t.x() << ',' << t.y() << ',' << t.z()
           << ',' << q.x() << ',' << q.y() << ',' << q.z() << ',' << q.w() << ",,,,,,,";
  PutMotionSigmas(motions_, &m.covariance);
  motions_ << '\n';
  speeds_ << m.frame << ',' << m.object_id << ',' << m.is_dynamic << ',' << m.speed_mps << ',';
  PutSpeedSigma(speeds_, m.speed_sigma_mps);
  speeds_ << '\n';
}

void StreamingFileSink::pointFinal(const PointEstimate& p) {
  open();
  points_ << (p.object_id < 0 ? -1 : p.frame) << ',' << p.object_id << ',' << p.p_world.x() << ',' << p.p_world.y()
          << ',' << p.p_world.z() << '\n';
}

void StreamingFileSink::flush() {
  if (!opened_) return;
  for (std::ofstream* f : {&camera_, &online_, &motions_, &speeds_, &points_}) {
    f->flush();
    if (!*f) throw std::runtime_error("error while writing the streamed results in " + dir_);
  }
}

}  // namespace dslam
