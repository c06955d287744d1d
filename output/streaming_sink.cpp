#include "output/streaming_sink.h"

#include <filesystem>
#include <iomanip>
#include <limits>
#include <stdexcept>

#include "evaluation/evaluate_run.h"
#include "output/object_rows.h"
#include "output/text_format.h"
#include "output/trajectory_io.h"

namespace dslam {
namespace {

constexpr const char* kMapPointsHeader = "frame,object_id,x,y,z";
constexpr int kDigits = 9;  // of every number written (decimals in the files written fixed)

void Open(const std::string& path, const std::string& header, bool fixed, WholeLineFile* out) {
  out->open(path);
  if (!*out) throw std::runtime_error("cannot write " + path);
  *out << std::setprecision(kDigits);
  if (fixed) *out << std::fixed;
  if (!header.empty()) *out << header << '\n';
}

// The first frame with a ground-truth pose of an object (its estimated_ bits start there).
int FirstPoseFrame(const GroundTruth& gt, int object_id) {
  const auto it = gt.objects.find(object_id);
  return it == gt.objects.end() || it->second.L_world_object.empty() ? 0 : it->second.L_world_object.begin()->first;
}

}  // namespace

StreamingFileSink::StreamingFileSink(const std::string& dir, StreamedFiles files, const GroundTruth* gt,
                                     double frame_rate_hz)
    : dir_(dir), files_(std::move(files)), gt_(gt), frame_rate_hz_(frame_rate_hz) {}

void StreamingFileSink::open() {
  if (opened_) return;
  opened_ = true;
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw std::runtime_error("cannot create output directory " + dir_ + ": " + ec.message());
  // The same formats (and, for the trajectories, the same number format) as the files written at the end.
  const std::string camera = dir_ + "/camera_" + files_.method;
  Open(camera + ".tum", "", true, &camera_);
  if (files_.kitti) Open(camera + ".kitti", "", true, &kitti_);
  if (files_.online) Open(camera + "_online.tum", "", true, &online_);
  if (files_.object_tables) {
    Open(dir_ + "/object_motions" + files_.object_suffix + ".csv", kObjectMotionsHeader, false, &motions_);
    Open(dir_ + "/object_speeds" + files_.object_suffix + ".csv", kObjectSpeedsHeader, false, &speeds_);
  }
  if (files_.map_points) Open(dir_ + "/map_points.csv", kMapPointsHeader, false, &points_);
}

void StreamingFileSink::frameStamp(int frame, int64_t t_ns) {
  open();
  stamps_.emplace_back(frame, t_ns);
}

void StreamingFileSink::onlinePose(int64_t t_ns, const SE3& T_world_camera) {
  open();
  if (!files_.online) return;
  PutTumLine(online_, t_ns, T_world_camera);
  online_.flush();
}

void StreamingFileSink::cameraFinal(int frame, const SE3& T_world_camera) {
  open();
  while (!stamps_.empty() && stamps_.front().first < frame) stamps_.pop_front();
  if (stamps_.empty() || stamps_.front().first != frame)
    throw std::logic_error("streaming sink: no stamp for frame " + std::to_string(frame));
  PutTumLine(camera_, stamps_.front().second, T_world_camera);
  writeLandmarksSeenBefore(frame);
  if (files_.kitti) PutKittiLine(kitti_, T_world_camera);
  stamps_.pop_front();
  flush();  // once per frame: each frame added makes at most one camera final
}

void StreamingFileSink::motionFinal(const ObjectMotionEstimate& m) {
  open();
  if (!files_.object_tables) return;
  std::optional<ObjectPairSample> pair;
  if (gt_) {
    // With the run's own object ids, the row keeps the run's id and carries the ground truth of the object
    // it was found to be (as WriteRunOutputs writes it).
    const std::optional<int> gt_id = GroundTruthIdOf(*gt_, m.object_id, m.frame);
    if (gt_id) pair = GroundTruthPair(*gt_, frame_rate_hz_, *gt_id, m.frame);
    if (pair) {
      std::vector<bool>& bits = estimated_[*gt_id];
      const size_t i = static_cast<size_t>(m.frame - FirstPoseFrame(*gt_, *gt_id));
      if (bits.size() <= i) bits.resize(i + 1, false);
      bits[i] = true;
    }
  }
  PutObjectRows(motions_, speeds_, m.object_id, m.frame, &m, pair ? &*pair : nullptr);
}

void StreamingFileSink::pointFinal(const PointEstimate& p) {
  open();
  if (!files_.map_points) return;
  if (p.object_id < 0) {  // a landmark: its latest value, written when its sighting ends
    landmarks_[p.track_id] = {p.frame, p.p_world};
    return;
  }
  putPoint(p.frame, p.object_id, p.p_world);
}

void StreamingFileSink::putPoint(int frame, int object_id, const Vec3& p_world) {
  points_ << frame << ',' << object_id;
  for (int a = 0; a < 3; ++a) {
    points_ << ',';
    PutGeneral(points_, p_world[a], kDigits);
  }
  points_ << '\n';
}

void StreamingFileSink::writeLandmarksSeenBefore(int frame) {
  // A frame's observations become final before its camera does: a landmark whose last final
  // observation is older than that camera is not seen in it, and its sighting has ended.
  for (auto it = landmarks_.begin(); it != landmarks_.end();) {
    if (it->second.first < frame) {
      putPoint(-1, -1, it->second.second);
      it = landmarks_.erase(it);
    } else {
      ++it;
    }
  }
}

void StreamingFileSink::flush() {
  if (!opened_) return;
  for (WholeLineFile* f : {&camera_, &kitti_, &online_, &motions_, &speeds_, &points_}) {
    if (!f->is_open()) continue;
    f->flush();
    if (!*f) throw std::runtime_error("error while writing the streamed results in " + dir_);
  }
}

void StreamingFileSink::finish() {
  writeLandmarksSeenBefore(std::numeric_limits<int>::max());
  // Pairs without estimate have no row when the run's object ids are its own: there is no id to give them.
  if (gt_ && files_.object_tables && !gt_->run_object_ids) {
    open();
    for (const auto& [id, obj] : gt_->objects) {
      const auto bits = estimated_.find(id);
      const int first = FirstPoseFrame(*gt_, id);
      for (int k : obj.observed_frames) {
        const size_t i = static_cast<size_t>(k - first);
        if (bits != estimated_.end() && i < bits->second.size() && bits->second[i]) continue;
        const std::optional<ObjectPairSample> pair = GroundTruthPair(*gt_, frame_rate_hz_, id, k);
        if (pair) PutObjectRows(motions_, speeds_, id, k, nullptr, &*pair);
      }
    }
  }
  flush();
}

}  // namespace dslam
