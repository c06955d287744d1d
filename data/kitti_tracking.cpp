#include "data/kitti_tracking.h"

#include <cmath>
#include <map>
#include <utility>
#include <set>
#include <stdexcept>

#include "data/text_parsing.h"

namespace dslam {
namespace {
// Positions farther than this (beyond the Earth's size) are corrupt records: squared in the metrics they
// would overflow into NaN instead of failing.
constexpr double kMaxPositionM = 1e7;
constexpr double kEarthRadiusM = 6378137.0;

Mat4 Homogeneous3x4(const std::vector<double>& v) {
  Mat4 T = Mat4::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) T(r, c) = v[r * 4 + c];
  return T;
}

// Reads non-empty lines with at least `min_fields` fields, handing each to `row`.
template <typename Row>
void ForEachRow(const std::string& path, size_t min_fields, size_t max_fields, Row row) {
  std::ifstream in = OpenText(path);
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const auto fields = SplitFields(line);
    if (fields.empty()) continue;
    if (fields.size() < min_fields || fields.size() > max_fields)
      throw std::runtime_error(AtLine(path, line_no,
                                      "expected " + std::to_string(min_fields) +
                                          (max_fields != min_fields ? "-" + std::to_string(max_fields) : "") +
                                          " fields, found " + std::to_string(fields.size())));
    row(fields, line_no);
  }
}
}  // namespace

Eigen::Matrix<double, 3, 4> KittiCalibration::P_camera_lidar() const {
  Mat4 rect = Mat4::Identity();
  rect.topLeftCorner<3, 3>() = R_rect;
  return P[2] * rect * T_cam_velo;
}

Eigen::Matrix<double, 3, 4> KittiCalibration::T_camera_lidar() const {
  const Eigen::Matrix3d K = P[2].leftCols<3>();
  return K.inverse() * P_camera_lidar();
}

Mat4 KittiCalibration::T_rect_imu() const {
  Mat4 R = Mat4::Identity();
  R.topLeftCorner<3, 3>() = R_rect;
  return R * T_cam_velo * T_velo_imu;
}

KittiCalibration ReadKittiCalibration(const std::string& path) {
  KittiCalibration calib;
  std::set<std::string> seen;
  std::ifstream in = OpenText(path);
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    auto fields = SplitFields(line);
    if (fields.empty()) continue;
    std::string key = fields[0];
    if (!key.empty() && key.back() == ':') key.pop_back();
    std::vector<double> v;
    for (size_t i = 1; i < fields.size(); ++i) v.push_back(ParseDouble(fields[i], path, line_no, key + " value"));
    auto need = [&](size_t n) {
      if (v.size() != n)
        throw std::runtime_error(AtLine(path, line_no, key + " needs " + std::to_string(n) + " numbers, found " +
                                                           std::to_string(v.size())));
    };
    if (key.size() == 2 && key[0] == 'P' && key[1] >= '0' && key[1] <= '3') {
      need(12);
      calib.P[key[1] - '0'] = Homogeneous3x4(v).topRows<3>();
    } else if (key == "R0_rect" || key == "R_rect") {
      need(9);
      for (int i = 0; i < 9; ++i) calib.R_rect(i / 3, i % 3) = v[i];
      key = "R_rect";
    } else if (key == "Tr_velo_to_cam" || key == "Tr_velo_cam") {
      need(12);
      calib.T_cam_velo = Homogeneous3x4(v);
      calib.has_T_cam_velo = true;
      key = "Tr_velo_cam";
    } else if (key == "Tr_imu_to_velo" || key == "Tr_imu_velo") {
      need(12);
      calib.T_velo_imu = Homogeneous3x4(v);
      key = "Tr_imu_velo";
    } else {
      continue;  // other calibration entries are not needed
    }
    seen.insert(key);
  }
  for (const char* required : {"P2", "R_rect"})
    if (!seen.count(required)) throw std::runtime_error(path + ": missing " + required);
  if (!(calib.fx() > 0.0 && calib.fy() > 0.0)) throw std::runtime_error(path + ": P2 has a non-positive focal length");
  // A camera's focal length and principal point are pixels: beyond 1e5 they are a corrupt or foreign file.
  constexpr double kMaxPixels = 1e5;
  if (calib.fx() > kMaxPixels || calib.fy() > kMaxPixels || std::abs(calib.cx()) > kMaxPixels ||
      std::abs(calib.cy()) > kMaxPixels)
    throw std::runtime_error(path + ": P2's focal length or principal point is beyond 1e5 pixels (fx " +
                             std::to_string(calib.fx()) + ", fy " + std::to_string(calib.fy()) + ")");
  return calib;
}

std::vector<KittiLabel> ReadKittiLabels(const std::string& path) {
  std::vector<KittiLabel> labels;
  int last_frame = -1;
  std::map<int, int> line_of_track;  // in the current frame: a second line for a track would replace the first
  // 17 fields, or 18 with a score (tracking results use the same format).
  ForEachRow(path, 17, 18, [&](const std::vector<std::string>& f, int line_no) {
    KittiLabel label;
    label.frame = ParseInt(f[0], path, line_no, "frame");
    label.track_id = ParseInt(f[1], path, line_no, "track id");
    label.type = f[2];
    std::vector<double> v;
    for (size_t i = 3; i < f.size(); ++i) v.push_back(ParseDouble(f[i], path, line_no, "label field " + std::to_string(i + 1)));
    if (label.frame < 0) throw std::runtime_error(AtLine(path, line_no, "negative frame number"));
    if (label.frame < last_frame)
      throw std::runtime_error(AtLine(path, line_no, "frame " + std::to_string(label.frame) + " out of order: after frame " +
                                                         std::to_string(last_frame)));
    if (label.frame != last_frame) line_of_track.clear();
    last_frame = label.frame;
    if (label.type == "DontCare") return;
    if (label.track_id < 0) throw std::runtime_error(AtLine(path, line_no, "negative track id on a " + label.type));
    if (const auto [it, is_new] = line_of_track.emplace(label.track_id, line_no); !is_new)
      throw std::runtime_error(AtLine(path, line_no, "track " + std::to_string(label.track_id) + " labelled twice in frame " +
                                                         std::to_string(label.frame) + " (first on line " +
                                                         std::to_string(it->second) + ")"));
    label.h = v[7];
    label.w = v[8];
    label.l = v[9];
    if (!(label.h > 0.0 && label.w > 0.0 && label.l > 0.0))
      throw std::runtime_error(AtLine(path, line_no, "object size h w l must be positive"));
    label.bottom_centre_camera = Vec3(v[10], v[11], v[12]);
    label.rotation_y = v[13];
    labels.push_back(label);
  });
  return labels;
}

std::vector<SE3> ReadPoseGt(const std::string& path) {
  std::vector<SE3> poses;
  ForEachRow(path, 17, 17, [&](const std::vector<std::string>& f, int line_no) {
    const int frame = ParseInt(f[0], path, line_no, "frame");
    if (frame != static_cast<int>(poses.size()))
      throw std::runtime_error(AtLine(path, line_no, "frame " + std::to_string(frame) + " out of order: expected " +
                                                         std::to_string(poses.size())));
    Mat4 T;
    for (int i = 0; i < 16; ++i) T(i / 4, i % 4) = ParseDouble(f[1 + i], path, line_no, "pose entry");
    const Mat3 R = T.topLeftCorner<3, 3>();
    if ((R * R.transpose() - Mat3::Identity()).norm() > 1e-3 || R.determinant() < 0.0)
      throw std::runtime_error(AtLine(path, line_no, "the rotation block is not a rotation"));
    if (T.topRightCorner<3, 1>().norm() > kMaxPositionM)
      throw std::runtime_error(AtLine(path, line_no, "the position is more than 1e7 m from the origin"));
    poses.push_back(SE3::FromMatrix(T));
  });
  if (poses.empty()) throw std::runtime_error(path + ": no poses");
  return poses;
}

std::vector<ObjectPoseRow> ReadObjectPoses(const std::string& path) {
  std::vector<ObjectPoseRow> rows;
  std::map<std::pair<int, int>, int> line_of;  // (frame, object id) -> line: an object has one pose a frame
  ForEachRow(path, 10, 10, [&](const std::vector<std::string>& f, int line_no) {
    ObjectPoseRow row;
    row.frame = ParseInt(f[0], path, line_no, "frame");
    row.object_id = ParseInt(f[1], path, line_no, "object id");
    for (int i = 2; i < 6; ++i) ParseDouble(f[i], path, line_no, "box corner");
    row.bottom_centre_camera = Vec3(ParseDouble(f[6], path, line_no, "X"), ParseDouble(f[7], path, line_no, "Y"),
                                    ParseDouble(f[8], path, line_no, "Z"));
    row.rotation_y = ParseDouble(f[9], path, line_no, "rotation_y");
    if (row.frame < 0 || row.object_id < 0) throw std::runtime_error(AtLine(path, line_no, "negative frame or object id"));
    if (row.bottom_centre_camera.norm() > kMaxPositionM)
      throw std::runtime_error(AtLine(path, line_no, "the position is more than 1e7 m from the camera"));
    if (const auto [it, added] = line_of.emplace(std::make_pair(row.frame, row.object_id), line_no); !added)
      throw std::runtime_error(AtLine(path, line_no, "object " + std::to_string(row.object_id) + " listed twice in frame " +
                                                         std::to_string(row.frame) + " (first on line " +
                                                         std::to_string(it->second) + ")"));
    rows.push_back(row);
  });
  return rows;
}

std::vector<double> ReadTimes(const std::string& path) {
  std::vector<double> times;
  ForEachRow(path, 1, 1, [&](const std::vector<std::string>& f, int line_no) {
    const double t = ParseDouble(f[0], path, line_no, "timestamp");
    // Stamps are kept as int64 nanoseconds: beyond about 292 years they would wrap to negative.
    constexpr double kMaxSeconds = 9.2e9;
    if (!(t >= 0.0 && t < kMaxSeconds))
      throw std::runtime_error(AtLine(path, line_no, "timestamp " + f[0] + " s is outside [0, 9.2e9) s"));
    if (!times.empty() && t < times.back()) throw std::runtime_error(AtLine(path, line_no, "time goes backwards"));
    if (!times.empty() && t == times.back())
      throw std::runtime_error(AtLine(path, line_no, "timestamp " + f[0] + " s repeats the previous line's"));
    times.push_back(t);
  });
  return times;
}

std::map<int, std::string> ReadObjectCategories(const std::string& path) {
  std::map<int, std::string> categories;
  ForEachRow(path, 2, 2, [&](const std::vector<std::string>& f, int line_no) {
    categories[ParseInt(f[0], path, line_no, "object id")] = f[1];
  });
  return categories;
}

std::vector<OxtsRecord> ReadOxts(const std::string& path) {
  std::vector<OxtsRecord> records;
  ForEachRow(path, 30, 30, [&](const std::vector<std::string>& f, int line_no) {
    OxtsRecord r;
    double* dst[6] = {&r.lat_deg, &r.lon_deg, &r.alt_m, &r.roll, &r.pitch, &r.yaw};
    for (int i = 0; i < 30; ++i) {
      const double v = ParseDouble(f[i], path, line_no, "oxts field " + std::to_string(i + 1));
      if (i < 6) *dst[i] = v;
    }
    if (std::abs(r.lat_deg) > 90.0) throw std::runtime_error(AtLine(path, line_no, "latitude out of range"));
    records.push_back(r);
  });
  if (records.empty()) throw std::runtime_error(path + ": no oxts records");
  return records;
}

std::vector<SE3> ImuPosesFromOxts(const std::vector<OxtsRecord>& oxts) {
  std::vector<SE3> poses;
  if (oxts.empty()) return poses;
  const double scale = std::cos(oxts.front().lat_deg * M_PI / 180.0);
  for (const auto& r : oxts) {
    const Vec3 t(scale * r.lon_deg * M_PI * kEarthRadiusM / 180.0,
                 scale * kEarthRadiusM * std::log(std::tan((90.0 + r.lat_deg) * M_PI / 360.0)), r.alt_m);
    const Mat3 R = (Eigen::AngleAxisd(r.yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(r.pitch, Vec3::UnitY()) *
                    Eigen::AngleAxisd(r.roll, Vec3::UnitX()))
                       .toRotationMatrix();
    poses.emplace_back(R, t);
  }
  return poses;
}

std::vector<SE3> CameraPosesFromOxts(const std::vector<OxtsRecord>& oxts, const KittiCalibration& calibration) {
  const auto imu = ImuPosesFromOxts(oxts);
  const SE3 C = SE3::FromMatrix(calibration.T_rect_imu());
  std::vector<SE3> poses;
  for (const auto& T : imu) poses.push_back(C * imu.front().inverse() * T * C.inverse());
  return poses;
}

SE3 ObjectPoseFromLabel(const Vec3& bottom_centre_camera, double rotation_y) {
  return SE3(Eigen::AngleAxisd(rotation_y, Vec3::UnitY()).toRotationMatrix(), bottom_centre_camera);
}

std::string CategoryOfKittiType(const std::string& type) {
  if (type == "Car" || type == "Van" || type == "Truck" || type == "Tram") return "VEHICLE";
  if (type == "Pedestrian" || type == "Person_sitting" || type == "Person") return "PEDESTRIAN";
  if (type == "Cyclist") return "BICYCLE";
  return "MISC";
}

}  // namespace dslam
