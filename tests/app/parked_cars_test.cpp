// Issue 13: a parked car must never be reported moving. The built-in city rendered for 60 frames (the
// demo's scene) passes parked cars at the kerb that leave the view at the image border and slide behind
// cars that drive with us; their tracks there used to stick to the border or to the occluding edge and
// read as cars doing 20-45 km/h.
#include <gtest/gtest.h>

#include "output/object_summary.h"
#include "pipeline/image_run.h"
#include "pipeline/run_sequence.h"
#include "support/rendered_city.h"
#include "pipeline/run_defaults.h"

namespace dslam {
namespace {

TEST(ParkedCars, NoParkedCarOfTheRenderedCityIsReportedMoving) {
  const std::string dir = test::RenderedCity("parked_cars_city", 60);
  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const Sequence images = RunImageFrontend(ImageDataset(dir, config.dataset), config, 0, nullptr, nullptr);
  RunSequenceOptions run;
  run.methods = {Method::kOurs};
  const MethodOutcome ours = RunSequence(images, config, run).at(Method::kOurs);

  int parked = 0;
  for (const ObjectSummary& o : SummariseObjects(images, ours.result.estimate)) {
    if (!o.mean_gt_speed_kmh || *o.mean_gt_speed_kmh > 0.1 || !o.mean_est_speed_kmh) continue;
    ++parked;
    EXPECT_LT(*o.mean_est_speed_kmh, 2.0) << "parked car " << o.object_id;
  }
  EXPECT_GE(parked, 4);
  ASSERT_TRUE(ours.metrics.objects && ours.metrics.objects->static_mean_speed_mps);
  EXPECT_LT(*ours.metrics.objects->static_mean_speed_mps, 0.1);
  // The moving cars keep their accuracy.
  ASSERT_TRUE(ours.metrics.objects->omse_pct);
  EXPECT_LT(*ours.metrics.objects->omse_pct, 1.0);
}

}  // namespace
}  // namespace dslam
