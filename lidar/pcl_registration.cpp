#include "lidar/pcl_module.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>

namespace dslam {
namespace {
using XyzCloud = pcl::PointCloud<pcl::PointXYZ>;

XyzCloud::Ptr Thinned(const std::vector<Eigen::Vector3f>& points, double voxel_m) {
  XyzCloud::Ptr cloud(new XyzCloud);
  cloud->reserve(points.size());
  for (const Eigen::Vector3f& p : points)
    if (p.allFinite()) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  if (voxel_m <= 0.0) return cloud;
  XyzCloud::Ptr thinned(new XyzCloud);
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setLeafSize(voxel_m, voxel_m, voxel_m);
  grid.setInputCloud(cloud);
  grid.filter(*thinned);
  return thinned;
}
}  // namespace

Registration RegisterPointsWithPcl(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                                   const Eigen::Isometry3d& guess_target_source, const ScanRegistrationParams& params) {
  const XyzCloud::Ptr src = Thinned(source, params.voxel_m), dst = Thinned(target, params.voxel_m);
  if (src->size() < 3 || dst->size() < 3)
    throw std::invalid_argument("registration needs at least 3 points in each set (have " +
                                std::to_string(src->size()) + " and " + std::to_string(dst->size()) + ")");
  XyzCloud aligned;
  Registration out;
  const Eigen::Matrix4f guess = guess_target_source.matrix().cast<float>();
  auto run = [&](auto& icp) {
    icp.setInputSource(src);
    icp.setInputTarget(dst);
    icp.setMaxCorrespondenceDistance(params.max_correspondence_m);
    icp.setMaximumIterations(params.max_iterations);
    icp.setTransformationEpsilon(1e-8);
    icp.align(aligned, guess);
    out.converged = icp.hasConverged();
    out.rms_m = std::sqrt(icp.getFitnessScore(params.max_correspondence_m * params.max_correspondence_m));
    out.T_target_source.matrix() = icp.getFinalTransformation().template cast<double>();
  };
  if (params.generalized) {
    pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> gicp;
    gicp.setCorrespondenceRandomness(std::min<int>(20, static_cast<int>(std::min(src->size(), dst->size())) - 1));
    run(gicp);
  } else {
    pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
    run(icp);
  }
  // Re-orthonormalise: the float round trip leaves a slightly non-orthogonal rotation.
  const Eigen::Quaterniond q(out.T_target_source.linear());
  out.T_target_source.linear() = q.normalized().toRotationMatrix();
  return out;
}

}  // namespace dslam
