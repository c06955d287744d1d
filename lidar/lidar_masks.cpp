#include "lidar/lidar_masks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace dslam {
namespace {

float ElevationDeg(const Eigen::Vector3f& p, const Eigen::Vector3f& origin, const Eigen::Vector3f& up) {
  const Eigen::Vector3f r = p - origin;
  const float sine = std::clamp(r.dot(up) / (r.norm() * up.norm()), -1.0f, 1.0f);
  return static_cast<float>(std::asin(sine) * 180.0 / M_PI);
}

// Sets every pixel of `mask` (CV_8U) that the background outside it cannot reach.
void FillHoles(cv::Mat& mask) {
  cv::Mat outside(mask.rows + 2, mask.cols + 2, CV_8U, cv::Scalar(0));
  mask.copyTo(outside(cv::Rect(1, 1, mask.cols, mask.rows)));
  cv::floodFill(outside, cv::Point(0, 0), cv::Scalar(128));
  mask.setTo(255, outside(cv::Rect(1, 1, mask.cols, mask.rows)) == 0);
}

}  // namespace

void LidarMaskParams::validate() const {
  segmentation.validate();
  if (splat_half_width_px < 0 || splat_half_width_px > 20 || splat_half_height_px < 0 || splat_half_height_px > 20)
    throw std::invalid_argument("lidar_masks splat_half_width_px and splat_half_height_px must be in 0..20");
  if (grow_px < 0 || grow_px > 50) throw std::invalid_argument("lidar_masks grow_px must be in 0..50");
  if (!(fov_top_deg > -30.0 && fov_top_deg < 90.0))
    throw std::invalid_argument("lidar_masks fov_top_deg must be in (-30, 90)");
  if (!(fov_top_margin_deg >= 0.0 && fov_top_margin_deg < 10.0))
    throw std::invalid_argument("lidar_masks fov_top_margin_deg must be in [0, 10)");
  if (!(truncated_top_height_m > 0.0 && truncated_top_height_m < 10.0))
    throw std::invalid_argument("lidar_masks truncated_top_height_m must be in (0, 10)");
}

LidarMaskResult LidarInstanceMask(const std::vector<Eigen::Vector3f>& points_camera,
                                  const Eigen::Vector3f& lidar_origin_camera, const Eigen::Vector3f& lidar_up_camera,
                                  const PinholeCamera& camera, const LidarMaskParams& params) {
  params.validate();
  const int W = camera.width, H = camera.height;
  // Points whose column falls in the image (with a margin, so that an object at the edge is clustered
  // whole); rows above or below still join their clusters.
  const double margin_px = 100.0;
  std::vector<bool> in_view(points_camera.size(), false);
  for (size_t i = 0; i < points_camera.size(); ++i) {
    const Eigen::Vector3f& p = points_camera[i];
    if (!(p.z() > 0.5f) || !p.allFinite()) continue;
    const double u = camera.fx * p.x() / p.z() + camera.cx;
    if (u < -margin_px || u > W + margin_px) continue;
    in_view[i] = true;
  }
  LidarMaskResult out;
  out.segmentation = SegmentLidarObjects(points_camera, params.segmentation, in_view);
  const LidarSegmentation& seg = out.segmentation;
  const int n_objects = static_cast<int>(seg.objects.size());

  std::vector<int> label_of(points_camera.size(), 0);
  for (int l = 0; l < n_objects; ++l)
    for (int i : seg.objects[l].point_indices) label_of[i] = l + 1;
  // An object's lowest returns lie within the ground's band and were taken for ground: those inside its
  // footprint are its own (its bumper, its wheels, the road seen under it).
  for (int i : seg.ground) {
    const Eigen::Vector2f xz(points_camera[i].x(), points_camera[i].z());
    for (int l = 0; l < n_objects; ++l)
      if ((xz.array() >= seg.objects[l].footprint_lo.array()).all() &&
          (xz.array() <= seg.objects[l].footprint_hi.array()).all()) {
        label_of[i] = l + 1;
        break;
      }
  }

  // Z-buffer of splats: the nearest point's label at each pixel (-1: no point).
  cv::Mat zbuf(H, W, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
  cv::Mat labels(H, W, CV_32S, cv::Scalar(-1));
  const int hx = params.splat_half_width_px, hy = params.splat_half_height_px;
  for (size_t i = 0; i < points_camera.size(); ++i) {
    if (!in_view[i]) continue;
    const Eigen::Vector3f& p = points_camera[i];
    const int u = static_cast<int>(std::lround(camera.fx * p.x() / p.z() + camera.cx));
    const int v = static_cast<int>(std::lround(camera.fy * p.y() / p.z() + camera.cy));
    if (u + hx < 0 || u - hx >= W || v + hy < 0 || v - hy >= H) continue;
    for (int y = std::max(0, v - hy); y <= std::min(H - 1, v + hy); ++y) {
      float* z = zbuf.ptr<float>(y);
      int32_t* l = labels.ptr<int32_t>(y);
      for (int x = std::max(0, u - hx); x <= std::min(W - 1, u + hx); ++x)
        if (p.z() < z[x]) z[x] = p.z(), l[x] = label_of[i];
    }
  }

  out.ids = cv::Mat(H, W, CV_32S, cv::Scalar(0));
  out.boxes.assign(n_objects, cv::Rect());
  for (int l = 1; l <= n_objects; ++l) {
    cv::Mat mine = labels == l;
    const cv::Rect box = cv::boundingRect(mine);
    if (box.area() == 0) continue;
    // Extend a cluster cut by the top of the scan up to a vehicle's height above the ground: above the
    // top scan line the camera still sees it, the LiDAR does not.
    const LidarObjectCluster& object = seg.objects[l - 1];
    float object_top_deg = -90.0f;
    for (int i : object.point_indices) object_top_deg = std::max(object_top_deg, ElevationDeg(points_camera[i], lidar_origin_camera, lidar_up_camera));
    cv::Rect roi = box;
    if (seg.ground_valid && object_top_deg > params.fov_top_deg - params.fov_top_margin_deg) {
      const Eigen::Vector3f& n = seg.ground_normal;
      const Eigen::Vector3f& c = object.centroid_camera;
      // The point at the wanted height above the centroid's foot, as high as the image allows.
      const float y_top = (static_cast<float>(params.truncated_top_height_m) - seg.ground_d - n.x() * c.x() - n.z() * c.z()) / n.y();
      const int v_top = std::max(0, static_cast<int>(std::floor(camera.fy * y_top / c.z() + camera.cy)));
      if (v_top < box.y) {
        for (int x = box.x; x < box.x + box.width; ++x) {
          int top = -1;
          for (int y = box.y; y < box.y + box.height && top < 0; ++y)
            if (mine.at<uchar>(y, x)) top = y;
          if (top < 0) continue;
          for (int y = v_top; y < top; ++y)
            if (labels.at<int32_t>(y, x) <= 0) mine.at<uchar>(y, x) = 255;
        }
        roi = cv::boundingRect(mine);
      }
    }
    // Close the gaps between scan lines and grow into pixels no nearer surface claims.
    const int pad = hy + params.grow_px + 1;
    roi = (roi - cv::Point(pad, pad) + cv::Size(2 * pad, 2 * pad)) & cv::Rect(0, 0, W, H);
    cv::Mat region = mine(roi).clone();
    cv::morphologyEx(region, region, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_RECT, {2 * hx + 1, 2 * hy + 3}));
    if (params.grow_px > 0)
      cv::dilate(region, region, cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * params.grow_px + 1, 2 * params.grow_px + 1}));
    // Fill the holes the scan leaves inside an object (dark paint, glass and chrome return nothing): a
    // pixel enclosed by the object is the object, or seen through it, never structure to track.
    FillHoles(region);
    const cv::Mat other = labels(roi);
    cv::Mat ids = out.ids(roi);
    for (int y = 0; y < roi.height; ++y) {
      const uchar* r = region.ptr<uchar>(y);
      const int32_t* o = other.ptr<int32_t>(y);
      int32_t* id = ids.ptr<int32_t>(y);
      // Pixels of another object stay its; a pixel already given to a nearer object (lower label) stays too.
      for (int x = 0; x < roi.width; ++x)
        if (r[x] && (o[x] <= 0 || o[x] == l) && id[x] == 0) id[x] = l;
    }
    out.boxes[l - 1] = cv::boundingRect(out.ids(roi) == l) + roi.tl();
  }
  return out;
}

}  // namespace dslam
