// PCL against Open3D for the point-cloud steps the LiDAR mask source and the LiDAR check take from a
// library (lidar/point_cloud_segmentation.cpp, lidar/scan_registration.cpp), on the same points of real
// KITTI scans: the ground plane (RANSAC, 200 iterations, 0.25 m), the Euclidean clustering of one point per
// 12.5 cm voxel (0.5 m; Open3D's DBSCAN with one point is the same relation), and generalized ICP of
// consecutive scans thinned to 0.15 m (1 m correspondences, 40 iterations). Prints median milliseconds a
// frame for each library and how far their results agree. Built only where Open3D is installed
// (libopen3d-dev; not in scripts/deps.txt: the product uses PCL).
// Usage: bench_point_cloud_libraries DATASET [FRAMES (default: all)]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>
#include <map>
#include <tuple>
#include <unordered_map>
#include <vector>

#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/GeneralizedICP.h>
#include <open3d/utility/Logging.h>
#include <pcl/ModelCoefficients.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/sac_segmentation.h>

#include "bench/percentile.h"
#include "data/image_dataset.h"

namespace {
using Clock = std::chrono::steady_clock;
using PclCloud = pcl::PointCloud<pcl::PointXYZ>;
constexpr double kGroundDistanceM = 0.25, kClusterToleranceM = 0.5, kRegistrationVoxelM = 0.15;

double MsSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

PclCloud::Ptr ToPcl(const std::vector<Eigen::Vector3f>& points) {
  PclCloud::Ptr cloud(new PclCloud);
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  return cloud;
}
open3d::geometry::PointCloud ToOpen3d(const std::vector<Eigen::Vector3f>& points) {
  open3d::geometry::PointCloud cloud;
  for (const auto& p : points) cloud.points_.push_back(p.cast<double>());
  return cloud;
}
// A plane a x + b y + c z + d = 0 with its normal up (-y in the camera frame) and unit length.
Eigen::Vector4d Upward(Eigen::Vector4d plane) {
  plane /= plane.head<3>().norm();
  return plane.y() > 0.0 ? Eigen::Vector4d(-plane) : plane;
}
// Each point's label as the smallest point index of its cluster: two clusterings are the same partition
// exactly when these agree.
std::vector<int> Canonical(const std::vector<int>& label) {
  std::unordered_map<int, int> first;
  std::vector<int> out(label.size());
  for (size_t i = 0; i < label.size(); ++i) out[i] = first.emplace(label[i], static_cast<int>(i)).first->second;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_point_cloud_libraries DATASET [FRAMES]\n");
    return 2;
  }
  try {
    open3d::utility::SetVerbosityLevel(open3d::utility::VerbosityLevel::Error);
    const dslam::ImageDataset dataset(argv[1], dslam::ImageDatasetOptions{});
    if (!dataset.hasLidar()) throw std::runtime_error(std::string(argv[1]) + " has no LiDAR scans");
    const int frames = std::min(dataset.size(), argc > 2 ? std::atoi(argv[2]) : dataset.size());
    std::vector<double> pcl_plane_ms, o3d_plane_ms, pcl_cluster_ms, o3d_cluster_ms, pcl_icp_ms, o3d_icp_ms;
    std::vector<double> normal_angle_deg, offset_m, icp_translation_diff_m, icp_rotation_diff_deg;
    int same_partitions = 0, clustered_frames = 0;
    long pcl_clusters = 0, o3d_clusters = 0;
    std::vector<Eigen::Vector3f> previous;
    for (int k = 0; k < frames; ++k) {
      const dslam::ImageFrame frame = dataset.read(k);
      std::vector<Eigen::Vector3f> near, ground_fit;
      for (const auto& p : frame.lidar_points_camera) {
        const float range = std::hypot(p.x(), p.z());
        if (!p.allFinite() || range > 40.0f) continue;
        near.push_back(p);
        if (range < 30.0f) ground_fit.push_back(p);
      }

      // Ground plane. PCL's model keeps the normal within 10 degrees of vertical while it samples; Open3D's
      // has no such constraint (on these scans the dominant plane is the road either way).
      auto t0 = Clock::now();
      pcl::SACSegmentation<pcl::PointXYZ> sac;
      sac.setOptimizeCoefficients(true);
      sac.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
      sac.setMethodType(pcl::SAC_RANSAC);
      sac.setAxis(Eigen::Vector3f(0.0f, 1.0f, 0.0f));
      sac.setEpsAngle(10.0 * M_PI / 180.0);
      sac.setDistanceThreshold(kGroundDistanceM);
      sac.setMaxIterations(200);
      sac.setInputCloud(ToPcl(ground_fit));
      pcl::PointIndices inliers;
      pcl::ModelCoefficients coefficients;
      sac.segment(inliers, coefficients);
      pcl_plane_ms.push_back(MsSince(t0));
      t0 = Clock::now();
      const auto [o3d_plane, o3d_inliers] = ToOpen3d(ground_fit).SegmentPlane(kGroundDistanceM, 3, 200);
      o3d_plane_ms.push_back(MsSince(t0));
      if (coefficients.values.size() != 4) continue;
      const Eigen::Vector4d pcl_plane = Upward(Eigen::Vector4d(coefficients.values[0], coefficients.values[1],
                                                               coefficients.values[2], coefficients.values[3]));
      const Eigen::Vector4d other = Upward(o3d_plane);
      normal_angle_deg.push_back(std::acos(std::min(1.0, pcl_plane.head<3>().dot(other.head<3>()))) * 180.0 / M_PI);
      offset_m.push_back(std::abs(pcl_plane.w() - other.w()));

      // Clustering of the same representatives (points between the ground and 4.5 m, one per voxel).
      std::vector<Eigen::Vector3f> representatives;
      std::map<std::tuple<int, int, int>, bool> seen;
      const double voxel = kClusterToleranceM / 4.0;
      for (const auto& p : near) {
        const double h = pcl_plane.head<3>().dot(p.cast<double>()) + pcl_plane.w();
        if (h <= kGroundDistanceM || h >= 4.5) continue;
        const auto key = std::make_tuple(static_cast<int>(std::floor(p.x() / voxel)),
                                         static_cast<int>(std::floor(p.y() / voxel)),
                                         static_cast<int>(std::floor(p.z() / voxel)));
        if (seen.emplace(key, true).second) representatives.push_back(p);
      }
      t0 = Clock::now();
      const PclCloud::Ptr cloud = ToPcl(representatives);
      pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
      tree->setInputCloud(cloud);
      pcl::EuclideanClusterExtraction<pcl::PointXYZ> clustering;
      clustering.setClusterTolerance(kClusterToleranceM);
      clustering.setMinClusterSize(1);
      clustering.setMaxClusterSize(static_cast<int>(cloud->size()));
      clustering.setSearchMethod(tree);
      clustering.setInputCloud(cloud);
      std::vector<pcl::PointIndices> clusters;
      clustering.extract(clusters);
      pcl_cluster_ms.push_back(MsSince(t0));
      std::vector<int> pcl_label(representatives.size(), -1);
      for (size_t c = 0; c < clusters.size(); ++c)
        for (int i : clusters[c].indices) pcl_label[static_cast<size_t>(i)] = static_cast<int>(c);
      t0 = Clock::now();
      const std::vector<int> o3d_label = ToOpen3d(representatives).ClusterDBSCAN(kClusterToleranceM, 1);
      o3d_cluster_ms.push_back(MsSince(t0));
      ++clustered_frames;
      same_partitions += Canonical(pcl_label) == Canonical(o3d_label) ? 1 : 0;
      pcl_clusters += static_cast<long>(clusters.size());
      o3d_clusters += o3d_label.empty() ? 0 : *std::max_element(o3d_label.begin(), o3d_label.end()) + 1;

      // Registration of the previous scan onto this one (both from where the sensor was: identity guess).
      if (!previous.empty()) {
        t0 = Clock::now();
        pcl::VoxelGrid<pcl::PointXYZ> grid;
        grid.setLeafSize(kRegistrationVoxelM, kRegistrationVoxelM, kRegistrationVoxelM);
        PclCloud::Ptr src(new PclCloud), dst(new PclCloud);
        grid.setInputCloud(ToPcl(previous));
        grid.filter(*src);
        grid.setInputCloud(ToPcl(near));
        grid.filter(*dst);
        pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> gicp;
        gicp.setInputSource(src);
        gicp.setInputTarget(dst);
        gicp.setMaxCorrespondenceDistance(1.0);
        gicp.setMaximumIterations(40);
        gicp.setTransformationEpsilon(1e-8);
        PclCloud aligned;
        gicp.align(aligned);
        pcl_icp_ms.push_back(MsSince(t0));
        const Eigen::Matrix4d T_pcl = gicp.getFinalTransformation().cast<double>();
        t0 = Clock::now();
        const auto o3d_src = ToOpen3d(previous).VoxelDownSample(kRegistrationVoxelM);
        const auto o3d_dst = ToOpen3d(near).VoxelDownSample(kRegistrationVoxelM);
        const auto result = open3d::pipelines::registration::RegistrationGeneralizedICP(
            *o3d_src, *o3d_dst, 1.0, Eigen::Matrix4d::Identity(),
            open3d::pipelines::registration::TransformationEstimationForGeneralizedICP(),
            open3d::pipelines::registration::ICPConvergenceCriteria(1e-6, 1e-6, 40));
        o3d_icp_ms.push_back(MsSince(t0));
        const Eigen::Matrix4d& T_o3d = result.transformation_;
        icp_translation_diff_m.push_back((T_pcl.block<3, 1>(0, 3) - T_o3d.block<3, 1>(0, 3)).norm());
        const Eigen::AngleAxisd dR(Eigen::Matrix3d(T_pcl.block<3, 3>(0, 0).transpose() * T_o3d.block<3, 3>(0, 0)));
        icp_rotation_diff_deg.push_back(std::abs(dR.angle()) * 180.0 / M_PI);
      }
      previous = near;
    }
    using dslam::bench::Percentile;
    std::printf("%s, %d frames (median ms a frame, PCL / Open3D)\n", argv[1], frames);
    std::printf("  ground plane (RANSAC):     %6.1f / %6.1f ms; planes differ by %.2f deg (median; max %.2f), %.3f m\n",
                Percentile(pcl_plane_ms, 0.5), Percentile(o3d_plane_ms, 0.5), Percentile(normal_angle_deg, 0.5),
                Percentile(normal_angle_deg, 1.0), Percentile(offset_m, 0.5));
    std::printf("  clustering (Euclidean):    %6.1f / %6.1f ms; the same partition in %d of %d frames (%ld / %ld clusters)\n",
                Percentile(pcl_cluster_ms, 0.5), Percentile(o3d_cluster_ms, 0.5), same_partitions, clustered_frames,
                pcl_clusters, o3d_clusters);
    std::printf("  registration (GICP):       %6.1f / %6.1f ms; results differ by %.4f m, %.4f deg (median; max %.4f m)\n",
                Percentile(pcl_icp_ms, 0.5), Percentile(o3d_icp_ms, 0.5), Percentile(icp_translation_diff_m, 0.5),
                Percentile(icp_rotation_diff_deg, 0.5), Percentile(icp_translation_diff_m, 1.0));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_point_cloud_libraries: %s\n", e.what());
    return 2;
  }
}
