// The staged pipeline (front-end and back-end on their own threads) computes what the sequential
// pipeline computes, frame by frame; a rejected frame is reported and skipped, or stops the run.
#include "pipeline/staged_pipeline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <mutex>
#include <thread>

#include <opencv2/imgproc.hpp>

#include "app/run_command.h"
#include "output/result_reader.h"
#include "output/trajectory_io.h"
#include "pipeline/thread_priority.h"
#include "pipeline/vehicle_pipeline.h"
#include "support/rendered_city.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

void ExpectSame(const FrameEstimate& a, const FrameEstimate& b) {
  EXPECT_EQ(a.t_ns, b.t_ns);
  EXPECT_EQ(a.frame, b.frame);
  EXPECT_EQ((a.T_world_camera.translation() - b.T_world_camera.translation()).norm(), 0.0) << a.frame;
  ASSERT_EQ(a.object_motions.size(), b.object_motions.size()) << a.frame;
  for (size_t i = 0; i < a.object_motions.size(); ++i) {
    EXPECT_EQ(a.object_motions[i].object_id, b.object_motions[i].object_id);
    EXPECT_EQ(a.object_motions[i].speed_mps, b.object_motions[i].speed_mps);
  }
}

TEST(StagedPipeline, EqualsTheSequentialPipelineAndCarriesARejectedFramesOdometry) {
  const std::string dir = test::RenderedCity("staged_city", 12);
  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const ImageDataset data(dir, config.dataset);
  constexpr int kRejected = 5;

  // Reference: the frames without frame 5, frame 6's odometry spanning 4 -> 6.
  VehiclePipeline sequential(config, data.camera(), data.frameRateHz());
  std::vector<FrameEstimate> reference;
  for (int k = 0; k < data.size(); ++k) {
    if (k == kRejected) continue;
    ImageFrame f = data.read(k);
    if (k == kRejected + 1) f.odometry = Compose(*data.read(kRejected).odometry, *f.odometry);
    reference.push_back(sequential.process(f));
  }

  std::mutex mutex;
  std::vector<FrameEstimate> estimates;
  std::vector<std::string> rejections;
  int measurements = 0;
  StagedPipelineCallbacks callbacks;
  callbacks.on_measurement = [&](const FrameMeasurement& m, const FrontendFrameStats&, double ms) {
    EXPECT_EQ(m.frame_index, measurements++);
    EXPECT_GE(ms, 0.0);
  };
  callbacks.on_estimate = [&](const FrameEstimate& e, const FrameMeasurement& m, const FrameTiming& t) {
    std::lock_guard<std::mutex> lock(mutex);
    EXPECT_EQ(e.t_ns, m.t_ns);
    // The frame's timing comes through both stages, each time after the one before.
    EXPECT_EQ(t.received_ns, e.t_ns + 1) << "the timing is the frame's own";
    EXPECT_GE(t.frontend_start_ns, t.assembled_ns);
    EXPECT_GE(t.frontend_end_ns, t.frontend_start_ns);
    EXPECT_GE(t.backend_start_ns, t.frontend_end_ns);
    EXPECT_GE(t.backend_end_ns, t.backend_start_ns);
    EXPECT_GT(t.backend_end_ns, t.assembled_ns);
    estimates.push_back(e);
  };
  callbacks.on_rejected = [&](const ImageFrame& f, const std::string& reason) {
    std::lock_guard<std::mutex> lock(mutex);
    rejections.push_back(reason);
  };
  // Capacity 1: the producer waits on the front-end and the front-end on the back-end all along.
  StagedPipeline staged(config, data.camera(), data.frameRateHz(), 1, callbacks);
  for (int k = 0; k < data.size(); ++k) {
    ImageFrame f = data.read(k);
    if (k == kRejected) f.depth_m = cv::Mat(10, 10, CV_32FC1, cv::Scalar(1.0f));  // another size than the image
    f.timing.received_ns = f.t_ns + 1;  // a marker, to tell that each estimate's timing is its frame's
    f.timing.assembled_ns = SteadyClockNs();
    ASSERT_TRUE(staged.push(f));
  }
  const MethodResult result = staged.finish();
  ASSERT_EQ(rejections.size(), 1u);
  EXPECT_NE(rejections[0].find("depth"), std::string::npos) << rejections[0];
  ASSERT_EQ(estimates.size(), reference.size());
  for (size_t k = 0; k < reference.size(); ++k) ExpectSame(estimates[k], reference[k]);
  ASSERT_EQ(result.online.size(), reference.size());
  const MethodResult sequential_result = sequential.finish();
  ASSERT_EQ(result.estimate.T_world_camera.size(), sequential_result.estimate.T_world_camera.size());
  for (size_t k = 0; k < result.estimate.T_world_camera.size(); ++k)
    EXPECT_EQ((result.estimate.T_world_camera[k].translation() - sequential_result.estimate.T_world_camera[k].translation())
                  .norm(),
              0.0);
  EXPECT_FALSE(staged.push(data.read(0)));  // finished
}

// An offline run favours the front-end: the back-end's thread, and only it, runs at a lower priority, and
// every estimate is the one the pipeline gives with equal priorities.
TEST(StagedPipeline, FavouringTheFrontendLowersTheBackendsPriorityOnlyAndChangesNoEstimate) {
  const std::string dir = test::RenderedCity("staged_city", 12);
  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const ImageDataset data(dir, config.dataset);
  const int nice_before = ThisThreadsNice();
  std::map<bool, std::vector<FrameEstimate>> estimates;
  std::map<bool, int> backend_nice;
  for (const bool favour : {false, true}) {
    StagedPipelineCallbacks callbacks;
    callbacks.on_estimate = [&](const FrameEstimate& e, const FrameMeasurement&, const FrameTiming&) {
      estimates[favour].push_back(e);
    };
    StagedPipeline staged(config, data.camera(), data.frameRateHz(), 4, callbacks);
    if (favour) staged.favourFrontend();
    for (int k = 0; k < data.size(); ++k) ASSERT_TRUE(staged.pushPrepared(data.read(k)));
    staged.finish();
    backend_nice[favour] = staged.backendNice();
  }
  EXPECT_EQ(backend_nice[false], nice_before);
  EXPECT_EQ(backend_nice[true], std::min(19, nice_before + StagedPipeline::kBackendYieldNiceSteps));
  EXPECT_EQ(ThisThreadsNice(), nice_before);  // the caller's thread (the reader) keeps its priority
  ASSERT_EQ(estimates[true].size(), static_cast<size_t>(data.size()));
  ASSERT_EQ(estimates[false].size(), estimates[true].size());
  for (size_t k = 0; k < estimates[true].size(); ++k) ExpectSame(estimates[true][k], estimates[false][k]);
}

TEST(StagedPipeline, PushNewestDropsWaitingFramesAndCarriesTheirOdometryOn) {
  const std::string dir = test::RenderedCity("staged_city", 12);
  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const ImageDataset data(dir, config.dataset);
  VehiclePipeline sequential(config, data.camera(), data.frameRateHz());
  std::map<int64_t, Vec3> reference;
  for (int k = 0; k < data.size(); ++k) {
    const FrameEstimate e = sequential.process(data.read(k));
    reference[e.t_ns] = e.T_world_camera.translation();
  }
  std::mutex mutex;
  std::vector<FrameEstimate> estimates;
  StagedPipelineCallbacks callbacks;
  callbacks.on_estimate = [&](const FrameEstimate& e, const FrameMeasurement&, const FrameTiming&) {
    std::lock_guard<std::mutex> lock(mutex);
    estimates.push_back(e);
  };
  StagedPipeline staged(config, data.camera(), data.frameRateHz(), 1, callbacks);
  std::vector<ImageFrame> frames;
  for (int k = 0; k < data.size(); ++k) frames.push_back(data.read(k));
  ASSERT_TRUE(staged.pushNewest(frames[0]));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the front-end takes the first frame
  for (size_t k = 1; k < frames.size(); ++k) ASSERT_TRUE(staged.pushNewest(frames[k]));  // far faster than it
  staged.finish();
  ASSERT_GE(estimates.size(), 2u);
  EXPECT_GT(staged.framesDropped(), 0u);
  EXPECT_EQ(estimates.size() + staged.framesDropped(), frames.size());
  EXPECT_EQ(estimates.back().t_ns, frames.back().t_ns);  // the newest frame is never the one dropped
  for (const FrameEstimate& e : estimates)  // the odometry of the dropped frames reached the next ones
    EXPECT_LT((e.T_world_camera.translation() - reference.at(e.t_ns)).norm(), 0.5) << e.t_ns;
}

TEST(StagedPipeline, ACameraWithoutASizeTakesItFromTheFirstFrameThatFitsItsIntrinsics) {
  // serve knows the intrinsics only: three tiny frames first used to fix the size, and every real frame
  // was rejected for the rest of the session.
  const std::string dir = test::RenderedCity("staged_city", 12);
  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const ImageDataset data(dir, config.dataset);
  PinholeCamera intrinsics = data.camera();
  EXPECT_EQ(FindSizeMismatch(intrinsics, intrinsics.width, intrinsics.height), "");
  EXPECT_NE(FindSizeMismatch(intrinsics, 40, 12), "");
  EXPECT_NE(FindSizeMismatch(intrinsics, 700, 200), "");  // holds the principal point, but near its edge
  intrinsics.width = intrinsics.height = 0;
  std::mutex mutex;
  std::vector<std::string> rejections;
  int estimates = 0;
  StagedPipelineCallbacks callbacks;
  callbacks.on_estimate = [&](const FrameEstimate&, const FrameMeasurement&, const FrameTiming&) {
    std::lock_guard<std::mutex> lock(mutex);
    ++estimates;
  };
  callbacks.on_rejected = [&](const ImageFrame&, const std::string& reason) {
    std::lock_guard<std::mutex> lock(mutex);
    rejections.push_back(reason);
  };
  StagedPipeline staged(config, intrinsics, data.frameRateHz(), 2, callbacks);
  for (int k = 0; k < 3; ++k) {
    ImageFrame tiny = data.read(k);
    cv::resize(tiny.image, tiny.image, cv::Size(40, 12));
    cv::resize(tiny.depth_m, tiny.depth_m, cv::Size(40, 12), 0, 0, cv::INTER_NEAREST);
    cv::resize(tiny.instance_ids, tiny.instance_ids, cv::Size(40, 12), 0, 0, cv::INTER_NEAREST);
    ASSERT_TRUE(staged.push(tiny));
  }
  for (int k = 3; k < data.size(); ++k) ASSERT_TRUE(staged.push(data.read(k)));
  staged.finish();
  ASSERT_EQ(rejections.size(), 3u);
  EXPECT_NE(rejections[0].find("40x12 image does not fit the calibration"), std::string::npos) << rejections[0];
  EXPECT_EQ(estimates, data.size() - 3);
}

TEST(StagedPipeline, WithoutARejectionHandlerABadFrameStopsItAndFinishThrowsTheError) {
  const std::string dir = test::RenderedCity("staged_city", 12);
  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const ImageDataset data(dir, config.dataset);
  StagedPipeline staged(config, data.camera(), data.frameRateHz(), 2, {});
  ASSERT_TRUE(staged.push(data.read(0)));
  ImageFrame bad = data.read(1);
  bad.depth_m = cv::Mat(10, 10, CV_32FC1, cv::Scalar(1.0f));
  staged.push(bad);
  bool refused = false;  // the front-end stopped: pushes fail soon after
  for (int i = 0; i < 200 && !refused; ++i) refused = !staged.push(data.read(2));
  EXPECT_TRUE(refused);
  EXPECT_THROW(staged.finish(), std::invalid_argument);
}

TEST(StagedPipeline, AsAServiceItKeepsNothingPerFrameAndItsFilesHoldEveryEstimate) {
  const std::string dir = test::RenderedCity("staged_city", 12);
  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const ImageDataset data(dir, config.dataset);
  VehiclePipeline sequential(config, data.camera(), data.frameRateHz());
  for (int k = 0; k < data.size(); ++k) sequential.process(data.read(k));
  const MethodResult reference = sequential.finish();

  const std::string out = test::TempPath("staged_service_out");
  StreamingFileSink stream(out);
  StagedPipeline staged(config, data.camera(), data.frameRateHz(), 2, {}, &stream, /*collect=*/false);
  for (int k = 0; k < data.size(); ++k) ASSERT_TRUE(staged.push(data.read(k)));
  const MethodResult result = staged.finish();
  EXPECT_TRUE(result.online.empty());
  EXPECT_TRUE(result.estimate.T_world_camera.empty());
  EXPECT_TRUE(result.estimate.points.empty());
  EXPECT_EQ(result.solve_times_ms.size(), 1u);  // only the last solve's: nothing grows per frame

  const std::vector<SE3> cameras = ReadTumTrajectory(out + "/camera_ours.tum");
  ASSERT_EQ(cameras.size(), reference.estimate.T_world_camera.size());
  for (size_t k = 0; k < cameras.size(); ++k)
    EXPECT_LT((cameras[k].translation() - reference.estimate.T_world_camera[k].translation()).norm(), 2e-9) << k;
  EXPECT_EQ(ReadTumTrajectory(out + "/camera_ours_online.tum").size(), 12u);
  const CsvTable speeds = ReadCsv(out + "/object_speeds.csv");
  EXPECT_EQ(speeds.rows.size(), reference.estimate.object_motions.size());
}

}  // namespace
}  // namespace dslam
