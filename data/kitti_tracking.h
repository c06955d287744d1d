#pragma once
// Readers for the KITTI tracking benchmark's files (KITTI's own layout) and the VDO-SLAM / DynoSAM
// ground-truth files. Every reader is strict: a short line, a non-number or an impossible value
// throws std::runtime_error "file:line: what is wrong".

#include <map>
#include <string>
#include <vector>

#include "geometry/se3.h"

namespace dslam {

struct KittiCalibration {
  Eigen::Matrix<double, 3, 4> P[4];                  // rectified projections of cameras 0..3
  Mat3 R_rect = Mat3::Identity();                    // R0_rect / R_rect
  Mat4 T_cam_velo = Mat4::Identity();                // Tr_velo_to_cam / Tr_velo_cam
  bool has_T_cam_velo = false;                       // the file gave it (LiDAR depth needs it)
  Mat4 T_velo_imu = Mat4::Identity();                // Tr_imu_to_velo / Tr_imu_velo
  double fx() const { return P[2](0, 0); }
  double fy() const { return P[2](1, 1); }
  double cx() const { return P[2](0, 2); }
  double cy() const { return P[2](1, 2); }
  // IMU -> rectified reference camera: R_rect * Tr_velo_to_cam * Tr_imu_to_velo.
  Mat4 T_rect_imu() const;
  // Velodyne -> pixels of the left colour camera: P2 * R_rect * Tr_velo_to_cam.
  Eigen::Matrix<double, 3, 4> P_camera_lidar() const;
  // Velodyne -> the left colour camera, metric [R | t]: K^-1 P2 R_rect Tr_velo_to_cam (P2 = K [I | t]).
  Eigen::Matrix<double, 3, 4> T_camera_lidar() const;
};
KittiCalibration ReadKittiCalibration(const std::string& path);

struct KittiLabel {
  int frame = 0;
  int track_id = -1;
  std::string type;  // Car, Van, Truck, Pedestrian, Person_sitting, Cyclist, Tram, Misc
  double h = 0, w = 0, l = 0;
  Vec3 bottom_centre_camera = Vec3::Zero();  // X Y Z in the rectified camera frame
  double rotation_y = 0.0;
};
// Tracked objects only: DontCare rows (track id -1) are validated and skipped.
std::vector<KittiLabel> ReadKittiLabels(const std::string& path);

// pose_gt.txt: "frame r11 r12 r13 t1 r21 ... t3 0 0 0 1" per line, frames 0, 1, 2, ... in order.
std::vector<SE3> ReadPoseGt(const std::string& path);

struct ObjectPoseRow {
  int frame = 0;
  int object_id = 0;
  Vec3 bottom_centre_camera = Vec3::Zero();
  double rotation_y = 0.0;
};
// object_pose.txt: "frame object_id x1 y1 x2 y2 X Y Z rotation_y", tab or space separated.
std::vector<ObjectPoseRow> ReadObjectPoses(const std::string& path);
// times.txt: one timestamp (s) per line, non-decreasing, in [0, 9.2e9) (int64 nanoseconds).
std::vector<double> ReadTimes(const std::string& path);
// object_category.txt: "object_id CATEGORY".
std::map<int, std::string> ReadObjectCategories(const std::string& path);

struct OxtsRecord {
  double lat_deg = 0, lon_deg = 0, alt_m = 0, roll = 0, pitch = 0, yaw = 0;
};
// oxts/SSSS.txt: 30 numbers per line (only the first six are used).
std::vector<OxtsRecord> ReadOxts(const std::string& path);
// World-from-IMU poses by KITTI's Mercator convention (scale from the first latitude), unnormalised.
std::vector<SE3> ImuPosesFromOxts(const std::vector<OxtsRecord>& oxts);
// Rectified-camera poses, world = the first camera: T_world_camera[k] = C * T_imu0^-1 * T_imuk * C^-1,
// C = calibration.T_rect_imu().
std::vector<SE3> CameraPosesFromOxts(const std::vector<OxtsRecord>& oxts, const KittiCalibration& calibration);

// Object pose from a label: origin at the box's bottom centre, rotation R_y(rotation_y).
SE3 ObjectPoseFromLabel(const Vec3& bottom_centre_camera, double rotation_y);
// KITTI type -> VDO-SLAM category: VEHICLE, PEDESTRIAN, BICYCLE, MISC.
std::string CategoryOfKittiType(const std::string& type);

}  // namespace dslam
