#pragma once
// What `dslam serve` must compute for a dataset fed as `dslam publish` feeds it: the frames through the same
// message round trip and assembly, then the online pipeline (as `dslam run` computes ours).

#include <string>
#include <vector>

#include "data/image_dataset.h"
#include "pipeline/vehicle_pipeline.h"
#include "plugin/frame_assembler.h"
#include "plugin/image_message.h"

namespace dslam::test {

inline std::vector<FrameEstimate> ServeReference(const std::string& dir, MethodResult* final_result = nullptr) {
  RunConfig config;
  config.backend.default_mode = MotionMode::kSmoothed;
  config.backend.schedule = {ScheduleKind::kSlidingWindow, 10};
  const ImageDataset data(dir, config.dataset);
  PinholeCamera camera = data.camera();
  VehiclePipeline pipeline(config, camera, data.frameRateHz());
  AssemblerParams params;
  params.expect_odometry = true;
  FrameAssembler assembler(params);
  SE3 T_odom_camera;
  std::vector<FrameEstimate> out;
  std::string error;
  int64_t previous_t_ns = 0;
  for (int k = 0; k < data.size(); ++k) {
    const ImageFrame f = data.read(k);
    Vec6 sigma = Vec6::Constant(0.01);
    if (f.odometry) T_odom_camera = T_odom_camera * f.odometry->T_prev_curr, sigma = f.odometry->sigma;
    assembler.addColour(f.t_ns, DecodeImage(EncodeImage(f.image, ImageRole::kColour, f.t_ns, "c"), ImageRole::kColour).image);
    assembler.addDepth(f.t_ns, DecodeImage(EncodeImage(f.depth_m, ImageRole::kDepth, f.t_ns, "c"), ImageRole::kDepth).image);
    cv::Mat ids;
    f.instance_ids.convertTo(ids, CV_16U);
    assembler.addMask(f.t_ns, DecodeImage(EncodeImage(ids, ImageRole::kMask, f.t_ns, "c"), ImageRole::kMask).image);
    // As dslam publish sends it: the increment's sigma per second since the previous frame.
    const double dt_s = k > 0 ? static_cast<double>(f.t_ns - previous_t_ns) * 1e-9 : 0.0;
    const Vec6 twist_sigma = dt_s > 0.0 ? Vec6(sigma / dt_s) : Vec6::Zero();
    previous_t_ns = f.t_ns;
    assembler.addOdometry(f.t_ns, *DecodeOdometry(EncodeOdometry(T_odom_camera, f.t_ns, "o", "c", twist_sigma), &error));
    for (const ImageFrame& ready : assembler.takeReady()) out.push_back(pipeline.process(ready));
  }
  if (final_result) *final_result = pipeline.finish();
  return out;
}

}  // namespace dslam::test
