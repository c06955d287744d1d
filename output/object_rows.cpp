#include "output/object_rows.h"

#include "output/text_format.h"

namespace dslam {
namespace {
void PutPose(std::ostream& out, const SE3* H) {
  if (!H) {
    out << ",,,,,,,";
    return;
  }
  const auto& t = H->translation();
  const auto& q = H->rotation();
  out << ',' << t.x() << ',' << t.y() << ',' << t.z() << ',' << q.x() << ',' << q.y() << ',' << q.z() << ',' << q.w();
}
}  // namespace

void PutObjectRows(std::ostream& motions, std::ostream& speeds, int object_id, int frame,
                   const ObjectMotionEstimate* est, const ObjectPairSample* gt) {
  motions << frame << ',' << object_id << ',';
  if (est) motions << est->is_dynamic;
  PutPose(motions, est ? &est->H_world : nullptr);
  PutPose(motions, gt ? &gt->H_world_gt : nullptr);
  PutMotionSigmas(motions, est ? &est->covariance : nullptr);
  motions << '\n';
  speeds << frame << ',' << object_id << ',';
  if (est) speeds << est->is_dynamic;
  speeds << ',';
  if (est) speeds << est->speed_mps;
  speeds << ',';
  if (gt) speeds << gt->speed_gt_mps;
  PutSpeedSigma(speeds, est ? est->speed_sigma_mps : 0.0);
  speeds << ',';
  if (est && !est->centroid_camera.isZero(0.0))
    speeds << est->centroid_camera.x() << ',' << est->centroid_camera.y() << ',' << est->centroid_camera.z();
  else
    speeds << ",,";
  speeds << ',';
  if (est && est->image_box)
    speeds << est->image_box->x << ',' << est->image_box->y << ',' << est->image_box->width << ',' << est->image_box->height;
  else
    speeds << ",,,";
  speeds << '\n';
}

}  // namespace dslam
