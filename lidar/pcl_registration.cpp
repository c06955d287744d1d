#include "lidar/pcl_module.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <pcl/features/normal_3d.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/correspondence_rejection_trimmed.h>
#include <pcl/registration/icp.h>
#include <pcl/search/kdtree.h>

namespace dslam {
namespace {
using XyzCloud = pcl::PointCloud<pcl::PointXYZ>;
using NormalCloud = pcl::PointCloud<pcl::PointNormal>;

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

// Each point with the normal of the plane through its nearest neighbours; points whose neighbours fit no
// plane (too few of them) are left out.
NormalCloud::Ptr WithNormals(const XyzCloud::Ptr& cloud, int neighbours) {
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  estimation.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  estimation.setInputCloud(cloud);
  estimation.setKSearch(std::min<int>(neighbours, static_cast<int>(cloud->size())));
  pcl::PointCloud<pcl::Normal> normals;
  estimation.compute(normals);
  NormalCloud::Ptr out(new NormalCloud);
  out->reserve(cloud->size());
  for (size_t i = 0; i < cloud->size(); ++i) {
    const pcl::Normal& n = normals[i];
    if (!std::isfinite(n.normal_x) || !std::isfinite(n.normal_y) || !std::isfinite(n.normal_z)) continue;
    pcl::PointNormal p;
    p.getVector3fMap() = (*cloud)[i].getVector3fMap();
    p.getNormalVector3fMap() = n.getNormalVector3fMap();
    p.curvature = n.curvature;
    out->push_back(p);
  }
  return out;
}
// Trimming keeps the pairs that are closest at the current estimate; far from the motion those are the pairs
// that do not tell it (a wall along the road, the ground's rings), so every pair is kept first and the
// closest only from where that converged.
template <typename Icp, typename CloudPtr, typename Setup>
void AlignInStages(const CloudPtr& source, const CloudPtr& target, const Eigen::Isometry3d& guess_target_source,
                   const ScanRegistrationParams& params, const Setup& setup, Registration& out) {
  Eigen::Matrix4f estimate = guess_target_source.matrix().cast<float>();
  for (const double kept : {1.0, params.kept_pair_fraction}) {
    Icp icp;
    setup(icp);
    icp.setInputSource(source);
    icp.setInputTarget(target);
    icp.setMaxCorrespondenceDistance(params.max_correspondence_m);
    icp.setMaximumIterations(params.max_iterations);
    icp.setTransformationEpsilon(1e-10);
    icp.setEuclideanFitnessEpsilon(1e-12);
    if (kept < 1.0) {
      auto trimmed = pcl::make_shared<pcl::registration::CorrespondenceRejectorTrimmed>();
      trimmed->setOverlapRatio(static_cast<float>(kept));
      icp.addCorrespondenceRejector(trimmed);
    }
    typename std::remove_reference_t<decltype(*source)> aligned;
    icp.align(aligned, estimate);
    estimate = icp.getFinalTransformation();
    out.converged = icp.hasConverged();
    out.rms_m = std::sqrt(icp.getFitnessScore(params.max_correspondence_m * params.max_correspondence_m));
    if (params.kept_pair_fraction >= 1.0) break;
  }
  out.T_target_source.matrix() = estimate.cast<double>();
}

}  // namespace

Registration RegisterPointsWithPcl(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                                   const Eigen::Isometry3d& guess_target_source, const ScanRegistrationParams& params) {
  const XyzCloud::Ptr src = Thinned(source, params.voxel_m), dst = Thinned(target, params.voxel_m);
  if (src->size() < 3 || dst->size() < 3)
    throw std::invalid_argument("registration needs at least 3 points in each set (have " +
                                std::to_string(src->size()) + " and " + std::to_string(dst->size()) + ")");
  Registration out;
  switch (params.metric) {
    case RegistrationMetric::kPointToPlane:
      AlignInStages<pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal>>(
          WithNormals(src, params.normal_neighbours), WithNormals(dst, params.normal_neighbours), guess_target_source,
          params, [](auto&) {}, out);
      break;
    case RegistrationMetric::kGeneralized: {
      const int randomness = std::min<int>(20, static_cast<int>(std::min(src->size(), dst->size())) - 1);
      AlignInStages<pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>>(
          src, dst, guess_target_source, params, [randomness](auto& gicp) { gicp.setCorrespondenceRandomness(randomness); },
          out);
      break;
    }
    case RegistrationMetric::kPointToPoint:
      AlignInStages<pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>>(src, dst, guess_target_source, params,
                                                                              [](auto&) {}, out);
      break;
  }
  // Re-orthonormalise: the float round trip leaves a slightly non-orthogonal rotation.
  const Eigen::Quaterniond q(out.T_target_source.linear());
  out.T_target_source.linear() = q.normalized().toRotationMatrix();
  return out;
}

}  // namespace dslam
