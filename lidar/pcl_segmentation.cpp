#include "lidar/pcl_module.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include <pcl/ModelCoefficients.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/sac_segmentation.h>

namespace dslam {
namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr Cloud(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& which) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->reserve(which.size());
  for (int i : which) cloud->push_back(pcl::PointXYZ(points[i].x(), points[i].y(), points[i].z()));
  return cloud;
}

}  // namespace

LidarSegmentation SegmentLidarObjectsWithPcl(const std::vector<Eigen::Vector3f>& points_camera,
                                             const LidarSegmentationParams& params, const std::vector<bool>& in_view) {
  LidarSegmentation out;
  std::vector<int> near, ground_fit;
  for (int i = 0; i < static_cast<int>(points_camera.size()); ++i) {
    const Eigen::Vector3f& p = points_camera[i];
    if (!p.allFinite() || (!in_view.empty() && !in_view[i])) continue;
    const float range = std::hypot(p.x(), p.z());
    if (range > params.max_range_m) continue;
    near.push_back(i);
    if (range < params.ground_fit_range_m) ground_fit.push_back(i);
  }
  if (near.empty()) return out;

  // The ground: the dominant plane whose normal is near the camera's vertical.
  if (ground_fit.size() >= 50) {
    pcl::SACSegmentation<pcl::PointXYZ> sac;
    sac.setOptimizeCoefficients(true);
    sac.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
    sac.setMethodType(pcl::SAC_RANSAC);
    sac.setAxis(Eigen::Vector3f(0.0f, 1.0f, 0.0f));
    sac.setEpsAngle(params.ground_max_tilt_deg * M_PI / 180.0);
    sac.setDistanceThreshold(params.ground_distance_m);
    sac.setMaxIterations(200);
    sac.setInputCloud(Cloud(points_camera, ground_fit));
    pcl::PointIndices inliers;
    pcl::ModelCoefficients plane;
    sac.segment(inliers, plane);
    if (plane.values.size() == 4 && inliers.indices.size() >= 50) {
      Eigen::Vector3f n(plane.values[0], plane.values[1], plane.values[2]);
      float d = plane.values[3];
      const float norm = n.norm();
      n /= norm, d /= norm;
      if (n.y() > 0.0f) n = -n, d = -d;  // up is -y in the camera frame
      out.ground_normal = n, out.ground_d = d, out.ground_valid = true;
    }
  }

  // Points between the ground and a truck's height are clustered; higher ones (bridges, crowns, upper
  // floors) are structure. A pillar under a bridge is then an object that stands still.
  std::vector<int> above;
  for (int i : near) {
    const float h = out.heightAboveGround(points_camera[i]);
    if (out.ground_valid && std::abs(h) < params.ground_distance_m) {
      out.ground.push_back(i);
      continue;
    }
    if (h > params.ground_distance_m && h < params.max_height_above_ground_m) above.push_back(i);
  }
  if (above.size() < static_cast<size_t>(params.min_cluster_points)) return out;

  // Cluster one representative point per voxel (a quarter of the tolerance across): near the sensor a car
  // has thousands of returns, and a radius search among all of them is what costs; every point then joins
  // its voxel's cluster.
  const float voxel = static_cast<float>(params.cluster_tolerance_m) / 4.0f;
  std::unordered_map<int64_t, int> voxel_of_key;
  std::vector<int> representative, voxel_of(above.size());
  for (size_t j = 0; j < above.size(); ++j) {
    const Eigen::Vector3f& p = points_camera[above[j]];
    const int64_t key = (static_cast<int64_t>(std::floor(p.x() / voxel)) + (1 << 20)) * (int64_t{1} << 42) +
                        (static_cast<int64_t>(std::floor(p.y() / voxel)) + (1 << 20)) * (int64_t{1} << 21) +
                        (static_cast<int64_t>(std::floor(p.z() / voxel)) + (1 << 20));
    const auto [it, added] = voxel_of_key.emplace(key, static_cast<int>(representative.size()));
    if (added) representative.push_back(above[j]);
    voxel_of[j] = it->second;
  }
  std::vector<std::vector<int>> members(representative.size());
  for (size_t j = 0; j < above.size(); ++j) members[voxel_of[j]].push_back(above[j]);

  const auto cloud = Cloud(points_camera, representative);
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  tree->setInputCloud(cloud);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> clustering;
  clustering.setClusterTolerance(params.cluster_tolerance_m);
  clustering.setMinClusterSize(1);
  clustering.setMaxClusterSize(static_cast<int>(cloud->size()));
  clustering.setSearchMethod(tree);
  clustering.setInputCloud(cloud);
  std::vector<pcl::PointIndices> clusters;
  clustering.extract(clusters);

  // A surface seen edge-on (a car's side, a roof) is sampled sparsely and can come out as a cluster of
  // its own; clusters are kept as they are (joining them by their footprints joined neighbouring vehicles).
  for (const pcl::PointIndices& c : clusters) {
    LidarObjectCluster object;
    for (int r : c.indices) object.point_indices.insert(object.point_indices.end(), members[r].begin(), members[r].end());
    if (static_cast<int>(object.point_indices.size()) < params.min_cluster_points) continue;
    object.footprint_lo = Eigen::Vector2f::Constant(1e9f), object.footprint_hi = -object.footprint_lo;
    float h_min = 1e9f, h_max = -1e9f;
    for (int i : object.point_indices) {
      const Eigen::Vector3f& p = points_camera[i];
      object.centroid_camera += p;
      const Eigen::Vector2f xz(p.x(), p.z());
      object.footprint_lo = object.footprint_lo.cwiseMin(xz), object.footprint_hi = object.footprint_hi.cwiseMax(xz);
      const float h = out.heightAboveGround(p);
      h_min = std::min(h_min, h), h_max = std::max(h_max, h);
    }
    object.centroid_camera /= static_cast<float>(object.point_indices.size());
    object.top_height_m = h_max;
    if (object.footprintDiagonal() > params.max_object_length_m || h_max - h_min < params.min_object_height_m ||
        h_min > params.max_object_base_height_m)
      continue;  // walls, kerbs, overhanging signs and crowns
    std::sort(object.point_indices.begin(), object.point_indices.end());
    out.objects.push_back(std::move(object));
  }
  std::sort(out.objects.begin(), out.objects.end(), [](const LidarObjectCluster& a, const LidarObjectCluster& b) {
    return a.centroid_camera.norm() < b.centroid_camera.norm();
  });
  return out;
}

}  // namespace dslam
