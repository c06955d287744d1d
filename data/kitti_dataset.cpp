#include "data/kitti_dataset.h"

#include <filesystem>
#include <stdexcept>

namespace dslam {
namespace {
namespace fs = std::filesystem;

std::optional<std::string> FirstExisting(const std::vector<fs::path>& candidates) {
  for (const auto& p : candidates)
    if (fs::is_regular_file(p)) return p.string();
  return std::nullopt;
}

// Typical box sizes (h, w, l) when only poses are given (VDO layout without labels).
void DefaultSize(const std::string& category, KittiObjectTrack* track) {
  track->size_from_labels = false;
  if (category == "PEDESTRIAN") {
    track->h = 1.75, track->w = 0.65, track->l = 0.85;
  } else if (category == "BICYCLE") {
    track->h = 1.7, track->w = 0.6, track->l = 1.75;
  } else {
    track->h = 1.55, track->w = 1.65, track->l = 4.0;
  }
}
}  // namespace

KittiGroundTruthSequence LoadKittiGroundTruth(const std::string& dir_in, const std::string& seq) {
  const fs::path dir(dir_in);
  if (!fs::is_directory(dir)) throw std::runtime_error("dataset directory " + dir_in + " does not exist");
  KittiGroundTruthSequence out;
  out.name = seq;

  const std::vector<fs::path> vdo_dirs = {dir / "gt" / seq, dir / seq, dir};
  auto vdo_file = [&](const std::string& name) {
    std::vector<fs::path> c;
    for (const auto& d : vdo_dirs) c.push_back(d / name);
    return FirstExisting(c);
  };

  if (const auto calib = FirstExisting({dir / "calib" / (seq + ".txt"), dir / "calib.txt"})) {
    out.calibration = ReadKittiCalibration(*calib);
    out.sources.push_back(*calib);
  }
  if (const auto poses = vdo_file("pose_gt.txt")) {
    out.T_world_camera = ReadPoseGt(*poses);
    out.sources.push_back(*poses);
  } else if (const auto oxts = FirstExisting({dir / "oxts" / (seq + ".txt")})) {
    if (!out.calibration)
      throw std::runtime_error(*oxts + ": camera poses from oxts need the calibration " +
                               (dir / "calib" / (seq + ".txt")).string());
    out.T_world_camera = CameraPosesFromOxts(ReadOxts(*oxts), *out.calibration);
    out.sources.push_back(*oxts);
  } else {
    throw std::runtime_error("no camera poses for sequence " + seq + " in " + dir_in +
                             ": expected gt/" + seq + "/pose_gt.txt, " + seq + "/pose_gt.txt, pose_gt.txt or oxts/" +
                             seq + ".txt");
  }
  const int num_frames = static_cast<int>(out.T_world_camera.size());
  // World = the first camera frame.
  const SE3 T0_inv = out.T_world_camera.front().inverse();
  for (auto& T : out.T_world_camera) T = T0_inv * T;

  if (const auto times = vdo_file("times.txt")) {
    const auto t = ReadTimes(*times);
    if (static_cast<int>(t.size()) < num_frames)
      throw std::runtime_error(*times + ": " + std::to_string(t.size()) + " timestamps for " +
                               std::to_string(num_frames) + " poses");
    out.sources.push_back(*times);
  }

  auto check_frame = [&](int frame, const std::string& file) {
    if (frame >= num_frames)
      throw std::runtime_error(file + ": frame " + std::to_string(frame) + " beyond the " +
                               std::to_string(num_frames) + " camera poses");
  };
  if (const auto labels = FirstExisting({dir / "label_02" / (seq + ".txt")})) {
    for (const auto& label : ReadKittiLabels(*labels)) {
      check_frame(label.frame, *labels);
      KittiObjectTrack& track = out.objects[label.track_id + 1];
      if (track.T_camera_object.empty()) {
        track.object_id = label.track_id + 1;
        track.type = label.type;
        track.category = CategoryOfKittiType(label.type);
        track.h = label.h, track.w = label.w, track.l = label.l;
      }
      track.T_camera_object[label.frame] = ObjectPoseFromLabel(label.bottom_centre_camera, label.rotation_y);
    }
    out.sources.push_back(*labels);
  } else if (const auto poses = vdo_file("object_pose.txt")) {
    std::map<int, std::string> categories;
    if (const auto cat = vdo_file("object_category.txt")) {
      categories = ReadObjectCategories(*cat);
      out.sources.push_back(*cat);
    }
    for (const auto& row : ReadObjectPoses(*poses)) {
      check_frame(row.frame, *poses);
      KittiObjectTrack& track = out.objects[row.object_id];
      if (track.T_camera_object.empty()) {
        track.object_id = row.object_id;
        const auto it = categories.find(row.object_id);
        track.category = it == categories.end() ? "VEHICLE" : it->second;
        DefaultSize(track.category, &track);
      }
      track.T_camera_object[row.frame] = ObjectPoseFromLabel(row.bottom_centre_camera, row.rotation_y);
    }
    out.sources.push_back(*poses);
  } else {
    throw std::runtime_error("no object ground truth for sequence " + seq + " in " + dir_in +
                             ": expected label_02/" + seq + ".txt or object_pose.txt");
  }
  return out;
}

GroundTruth ToUnobservedGroundTruth(const KittiGroundTruthSequence& gt, int num_frames) {
  if (num_frames > static_cast<int>(gt.T_world_camera.size()))
    throw std::invalid_argument("ground truth has " + std::to_string(gt.T_world_camera.size()) + " poses for " +
                                std::to_string(num_frames) + " frames");
  GroundTruth out;
  out.T_world_camera.assign(gt.T_world_camera.begin(), gt.T_world_camera.begin() + num_frames);
  for (const auto& [id, track] : gt.objects) {
    ObjectGroundTruth o;
    o.object_id = id;
    o.category = track.category;
    o.box_lwh = Vec3(track.l, track.w, track.h);
    const Vec3 centroid_body(0.0, -track.h / 2.0, 0.0);
    for (const auto& [k, T_camera_object] : track.T_camera_object) {
      if (k >= num_frames) continue;
      o.L_world_object[k] = out.T_world_camera[k] * T_camera_object;
      o.centroid_world[k] = o.L_world_object[k] * centroid_body;
    }
    if (!o.L_world_object.empty()) out.objects[id] = std::move(o);
  }
  return out;
}

void ObserveFrame(int frame, double object_max_range_m, const std::function<bool(int, int)>& visible, GroundTruth* gt) {
  const SE3 T_camera_world = gt->T_world_camera.at(frame).inverse();
  for (auto& [id, o] : gt->objects) {
    const auto centroid = o.centroid_world.find(frame);
    if (centroid == o.centroid_world.end()) continue;
    if ((T_camera_world * centroid->second).norm() < object_max_range_m && visible(frame, id))
      o.observed_frames.insert(frame);
  }
}

GroundTruth ToGroundTruth(const KittiGroundTruthSequence& gt, int num_frames, double object_max_range_m,
                          const std::function<bool(int, int)>& visible) {
  GroundTruth out = ToUnobservedGroundTruth(gt, num_frames);
  for (int k = 0; k < num_frames; ++k) ObserveFrame(k, object_max_range_m, visible, &out);
  return out;
}

}  // namespace dslam
