// The online pipeline that `dslam serve` runs computes what `dslam run` records for ours, frame by frame.
#include "pipeline/vehicle_pipeline.h"

#include <gtest/gtest.h>

#include <sstream>

#include "app/run_command.h"
#include "pipeline/image_run.h"
#include "pipeline/run_sequence.h"
#include "support/rendered_city.h"
#include "pipeline/run_defaults.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

TEST(VehiclePipeline, MatchesTheOnlineEstimatesOfDslamRun) {
  const std::string dir = test::RenderedCity("pipeline_city", 15);
  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const ImageDataset data(dir, config.dataset);
  RunSequenceOptions run;
  run.methods = {Method::kOurs};
  run.evaluate = false;
  const auto outcomes = RunSequence(RunImageFrontend(data, config, 0, nullptr, nullptr), config, run);
  const std::vector<FrameEstimate>& recorded = outcomes.at(Method::kOurs).result.online;
  ASSERT_EQ(recorded.size(), 15u);

  VehiclePipeline pipeline(config, data.camera(), data.frameRateHz());
  for (int k = 0; k < data.size(); ++k) {
    const FrameEstimate e = pipeline.process(data.read(k));
    EXPECT_EQ(e.t_ns, recorded[k].t_ns);
    EXPECT_LT((e.T_world_camera.translation() - recorded[k].T_world_camera.translation()).norm(), 1e-12) << k;
    ASSERT_EQ(e.object_motions.size(), recorded[k].object_motions.size()) << k;
    for (size_t i = 0; i < e.object_motions.size(); ++i)
      EXPECT_NEAR(e.object_motions[i].speed_mps, recorded[k].object_motions[i].speed_mps, 1e-12);
  }
  EXPECT_EQ(pipeline.framesProcessed(), 15);
  ImageFrame bad = data.read(0);
  bad.frame_index = 99;
  bad.depth_m = cv::Mat(10, 10, CV_32FC1);
  EXPECT_THROW(pipeline.process(bad), std::invalid_argument);
  EXPECT_EQ(pipeline.framesProcessed(), 15);
}

}  // namespace
}  // namespace dslam
