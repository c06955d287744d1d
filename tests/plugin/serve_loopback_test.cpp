// dslam serve and dslam publish as separate processes on this host (shared memory / loopback), each
// test on its own DDS domain, with an in-test participant listening to (or writing) the topics.
#include <gtest/gtest.h>
#include <signal.h>
#include <Eigen/Eigenvalues>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <algorithm>
#include <set>
#include <thread>
#include <nlohmann/json.hpp>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <fastdds/rtps/transport/test_UDPv4TransportDescriptor.h>

#include "app/render_scene_command.h"
#include "data/image_dataset.h"
#include "dslam_msgsPubSubTypes.h"
#include "nav_msgs_OdometryPubSubTypes.h"
#include "output/trajectory_io.h"
#include "pipeline/vehicle_pipeline.h"
#include "plugin/dds_session.h"
#include "plugin/frame_assembler.h"
#include "plugin/image_message.h"
#include "plugin/topics.h"
#include "sensor_msgs_ImagePubSubTypes.h"
#include "support/child_process.h"
#include "support/dds_domain.h"
#include "support/dds_profiles.h"
#include "support/no_display.h"
#include "support/rendered_city.h"
#include "support/serve_reference.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;
namespace dds = eprosima::fastdds::dds;
using namespace std::chrono_literals;

const std::string kProfiles = std::string(DSLAM_SOURCE_DIR) + "/config/dds_profiles.xml";


std::string CityDataset(int frames, uint64_t seed) {
  return test::RenderedCity("dds_city_" + std::to_string(frames) + "_" + std::to_string(seed), frames, seed);
}

// Listens to one vehicle's outputs.
class Listener {
 public:
  Listener(int domain, const std::string& vehicle)
      : session_(domain, kProfiles), odometry_(this), objects_(this), status_(this) {
    const VehicleTopics t = TopicsFor(vehicle);
    readers_ = {
        session_.reader(t.camera_odometry, new nav_msgs::msg::OdometryPubSubType(), "estimate_reader", &odometry_),
        session_.reader(t.object_motions, new dslam_msgs::msg::ObjectMotionArrayPubSubType(), "estimate_reader",
                        &objects_),
        session_.reader(t.status, new dslam_msgs::msg::StatusPubSubType(), "estimate_reader", &status_)};
    // Estimates are not kept for late joiners: wait until serve's writers are matched (discovery; slow
    // on a loaded machine).
    for (int i = 0; i < 600 && !matched(); ++i) std::this_thread::sleep_for(50ms);
  }
  bool matched() {
    for (dds::DataReader* r : readers_) {
      dds::SubscriptionMatchedStatus status;
      r->get_subscription_matched_status(status);
      if (status.current_count == 0) return false;
    }
    return true;
  }
  std::string summary() {
    std::lock_guard<std::mutex> lock(mutex);
    std::string s = std::to_string(poses_by_stamp.size()) + " poses received (stamps ms:";
    for (const auto& [t_ns, pose] : poses_by_stamp) s += " " + std::to_string(t_ns / 1'000'000);
    s += ")";
    if (!statuses.empty()) {
      const auto& st = statuses.back();
      s += "; serve: " + std::to_string(st.frames_received()) + " samples, " + std::to_string(st.frames_assembled()) +
           " assembled, " + std::to_string(st.dropped_incomplete()) + " incomplete, " +
           std::to_string(st.dropped_queue_full()) + " queue-full, " + std::to_string(st.samples_lost()) + " lost, " +
           std::to_string(st.rejected_invalid()) + " rejected (" + st.last_rejection() + ")";
    }
    return s;
  }
  // Polls `condition` (called under the lock) until it holds or `timeout` passes.
  template <typename Condition>
  bool waitUntil(Condition condition, std::chrono::seconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (condition()) return true;
      }
      std::this_thread::sleep_for(50ms);
    }
    return false;
  }
  bool waitFor(size_t poses, std::chrono::seconds timeout) {
    return waitUntil([&] { return poses_by_stamp.size() >= poses; }, timeout);
  }
  // A frame's status is published after its estimate: wait for the status that counts `frames` processed.
  bool waitForStatusAfter(uint64_t frames, std::chrono::seconds timeout) {
    return waitUntil([&] { return !statuses.empty() && statuses.back().frames_processed() >= frames; }, timeout);
  }

  std::mutex mutex;
  std::map<int64_t, SE3> poses_by_stamp;
  size_t odometry_samples = 0;  // every camera estimate received (a stamp received twice counts twice)
  std::map<int64_t, dslam_msgs::msg::ObjectMotionArray> objects_by_stamp;
  std::vector<dslam_msgs::msg::Status> statuses;

 private:
  template <typename Msg, typename F>
  struct TypedListener : dds::DataReaderListener {
    explicit TypedListener(Listener* l) : owner(l) {}
    void on_data_available(dds::DataReader* reader) override {
      Msg msg;
      dds::SampleInfo info;
      while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK)
        if (info.valid_data) F()(owner, msg);
    }
    Listener* owner;
  };
  struct OnOdometry {
    void operator()(Listener* l, const nav_msgs::msg::Odometry& m) {
      std::string error;
      const auto pose = DecodeOdometry(m, &error);
      std::lock_guard<std::mutex> lock(l->mutex);
      l->poses_by_stamp[StampToNs(m.header().stamp())] = pose->T_odom_camera;
      ++l->odometry_samples;
    }
  };
  struct OnObjects {
    void operator()(Listener* l, const dslam_msgs::msg::ObjectMotionArray& m) {
      std::lock_guard<std::mutex> lock(l->mutex);
      l->objects_by_stamp[StampToNs(m.header().stamp())] = m;
    }
  };
  struct OnStatus {
    void operator()(Listener* l, const dslam_msgs::msg::Status& m) {
      std::lock_guard<std::mutex> lock(l->mutex);
      l->statuses.push_back(m);
    }
  };
  DdsSession session_;
  std::vector<dds::DataReader*> readers_;
  TypedListener<nav_msgs::msg::Odometry, OnOdometry> odometry_;
  TypedListener<dslam_msgs::msg::ObjectMotionArray, OnObjects> objects_;
  TypedListener<dslam_msgs::msg::Status, OnStatus> status_;
};

void ExpectSameEstimates(const std::vector<FrameEstimate>& reference, Listener& listener) {
  std::lock_guard<std::mutex> lock(listener.mutex);
  ASSERT_EQ(listener.poses_by_stamp.size(), reference.size());
  int moving_with_covariance = 0;
  for (const FrameEstimate& e : reference) {
    const SE3& received = listener.poses_by_stamp.at(e.t_ns);
    EXPECT_LT((received.translation() - e.T_world_camera.translation()).norm(), 1e-9) << e.t_ns;
    EXPECT_LT(received.rotation().angularDistance(e.T_world_camera.rotation()), 1e-9) << e.t_ns;
    const auto& objects = listener.objects_by_stamp.at(e.t_ns).objects();
    ASSERT_EQ(objects.size(), e.object_motions.size()) << e.t_ns;
    for (size_t i = 0; i < objects.size(); ++i) {
      EXPECT_EQ(objects[i].object_id(), e.object_motions[i].object_id);
      EXPECT_NEAR(objects[i].h_world().position().x(), e.object_motions[i].H_world.translation().x(), 1e-9);
      EXPECT_NEAR(objects[i].h_world().position().z(), e.object_motions[i].H_world.translation().z(), 1e-9);
      EXPECT_NEAR(objects[i].speed_mps(), e.object_motions[i].speed_mps, 1e-9);
      // Velocity in m/s (the city is rendered at serve's default 10 Hz), centroid at k = H c_{k-1}.
      const auto& v = objects[i].velocity_mps();
      EXPECT_LT((Vec3(v.x(), v.y(), v.z()) - e.object_motions[i].velocity_world_per_frame * 10.0).norm(), 1e-9);
      const auto& c = objects[i].centroid_world();
      const Vec3 centroid_k = e.object_motions[i].centroidWorld();
      EXPECT_LT((Vec3(c.x(), c.y(), c.z()) - centroid_k).norm(), 1e-9);
      EXPECT_EQ(objects[i].is_dynamic(), e.object_motions[i].is_dynamic);
      // Where the object is in the frame: its points' centroid in the camera, its mask's box in the image.
      const auto& cc = objects[i].centroid_camera();
      EXPECT_LT((Vec3(cc.x(), cc.y(), cc.z()) - e.object_motions[i].centroid_camera).norm(), 1e-9);
      EXPECT_GT(cc.z(), 0.5);
      ASSERT_TRUE(e.object_motions[i].image_box);
      EXPECT_EQ(objects[i].box_x(), e.object_motions[i].image_box->x);
      EXPECT_EQ(objects[i].box_height(), e.object_motions[i].image_box->height);
      EXPECT_GT(objects[i].box_width(), 0);
      // The motion's covariance, row-major: the reference's, and for a moving object a covariance
      // (symmetric, positive definite).
      Mat6 covariance;
      for (int j = 0; j < 36; ++j) covariance(j / 6, j % 6) = objects[i].covariance()[static_cast<size_t>(j)];
      EXPECT_LT((covariance - e.object_motions[i].covariance).norm(), 1e-12);
      if (objects[i].is_dynamic()) {
        ++moving_with_covariance;
        EXPECT_LT((covariance - covariance.transpose()).norm(), 1e-9 * covariance.norm());
        EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat6>(covariance).eigenvalues().minCoeff(), 0.0) << e.t_ns;
      }
    }
  }
  EXPECT_GT(moving_with_covariance, 0);
}

// Two vehicles' listeners: every frame arrives, and each vehicle's estimates equal its own reference.
void ExpectBothEqualTheirReferences(Listener& a, const std::string& city_a, Listener& b, const std::string& city_b,
                                    size_t frames) {
  ASSERT_TRUE(a.waitFor(frames, 60s)) << a.summary();
  ASSERT_TRUE(b.waitFor(frames, 60s)) << b.summary();
  ExpectSameEstimates(test::ServeReference(city_a), a);
  ExpectSameEstimates(test::ServeReference(city_b), b);
}

// The shipped profiles with lossless sensor streams, for serve and the publishers. Written once per
// process: rewriting it for every child would truncate the file while an earlier child may be reading it.
const std::string& LosslessProfiles() {
  static const std::string path = test::WithLosslessSensorStreams(kProfiles, test::TempPath("lossless_profiles.xml"));
  return path;
}

// Generous timeouts: a loaded machine may stall a publisher between the parts of a frame. Every frame is
// estimated (--every-frame), so that the estimates can be compared with a recorded run's.
std::vector<std::string> ServeArgs(int domain, const std::string& dataset, const std::string& out,
                                   const std::string& silence_ms = "30000") {
  return {"serve", "--domain", std::to_string(domain), "--profiles", LosslessProfiles(), "--calib", dataset + "/calib.txt",
          "--out", out, "--status-every", "0", "--max-pending", "64", "--max-pending-mb", "2048", "--timeout-ms", "5000",
          "--silence-ms", silence_ms, "--every-frame"};
}

// The same without shared memory: the publisher reaches serve over UDP, as a camera driver on another host.
const std::string& LosslessUdpProfiles() {
  static const std::string path = test::WithoutSharedMemory(LosslessProfiles(), test::TempPath("lossless_udp.xml"));
  return path;
}

std::vector<std::string> PublishArgs(int domain, const std::string& dataset, const std::string& rate,
                                     const std::string& profiles = LosslessProfiles()) {
  return {"publish", "--domain", std::to_string(domain), "--profiles", profiles, "--dataset", dataset,
          "--rate", rate, "--wait", "60"};
}

TEST(ServeLoopback, EstimatesEqualTheRecordedRunAndSigtermWritesTheResults) {
  const std::string dataset = CityDataset(100, 1);
  const int domain = test::DomainFor(test::DdsTestSlot::kLoopbackEqual);
  const std::string out = test::TempPath("serve_out");
  test::Process serve(ServeArgs(domain, dataset, out), test::TempPath("serve.log"));
  Listener listener(domain, "");
  test::Process publish(PublishArgs(domain, dataset, "20"), test::TempPath("publish.log"));
  ASSERT_EQ(publish.wait(120s), 0) << test::ReadFile(test::TempPath("publish.log"));
  const std::vector<FrameEstimate> reference = test::ServeReference(dataset);
  ASSERT_TRUE(listener.waitFor(reference.size(), 240s)) << listener.summary();
  ExpectSameEstimates(reference, listener);

  serve.signal(SIGTERM);
  ASSERT_EQ(serve.wait(60s), 0) << test::ReadFile(test::TempPath("serve.log"));
  std::ifstream tum(out + "/default/camera_ours.tum");
  int lines = 0;
  for (std::string line; std::getline(tum, line);) lines += !line.empty() && line[0] != '#';
  EXPECT_EQ(lines, 100);
  EXPECT_TRUE(fs::exists(out + "/default/camera_ours_online.tum"));
  EXPECT_NE(test::ReadFile(test::TempPath("serve.log")).find("100 frames, results written to"), std::string::npos);
  // The latency budget over the session, per stage, each over every frame estimated.
  std::ifstream metrics_file(out + "/default/metrics.json");
  const nlohmann::json session = nlohmann::json::parse(metrics_file)["run"];
  EXPECT_EQ(session["frames_missing"].get<int>(), 0) << session.dump();  // every stamp of the 100 came
  const nlohmann::json latency = session["latency_ms"];
  for (const char* stage : {"input", "decode", "frontend_wait", "frontend", "backend_wait", "backend", "publish", "total"}) {
    ASSERT_TRUE(latency.contains(stage)) << stage << ": " << latency.dump();
    EXPECT_EQ(latency[stage]["frames"].get<int>(), 100) << stage;
    EXPECT_LE(latency[stage]["median_ms"].get<double>(), latency[stage]["p99_ms"].get<double>()) << stage;
  }
  EXPECT_GT(latency["frontend"]["median_ms"].get<double>(), 0.0);
  EXPECT_GT(latency["total"]["median_ms"].get<double>(), latency["frontend"]["median_ms"].get<double>());
}

TEST(ServeLoopback, ASecondSignalDropsTheBacklogAndStillWritesWhatWasEstimated) {
  // Under overload, a stop used to work through the whole backlog first (480 s with --max-pending 1000),
  // ignoring further signals.
  const std::string dataset = CityDataset(100, 1);
  const int domain = test::DomainFor(test::DdsTestSlot::kLoopbackSecondSignal);
  const std::string out = test::TempPath("serve_second_signal_out");
  const std::string log = test::TempPath("serve_second_signal.log");
  std::vector<std::string> args = ServeArgs(domain, dataset, out);
  const auto status_every = std::find(args.begin(), args.end(), "--status-every");
  ASSERT_NE(status_every, args.end());
  *(status_every + 1) = "0.3";  // console status lines while the backlog is worked on
  // A deliberately slow back-end (a 40-frame window with 40-frame object chains): the frames arrive far
  // faster than they are estimated, and a backlog builds up.
  const std::string slow = test::TempPath("slow_backend.yaml");
  std::ofstream(slow) << "backend:\n  schedule: window:40\n  object_window_frames: 40\n";
  args.insert(args.end(), {"--config", slow});
  test::Process serve(args, log);
  Listener listener(domain, "");
  test::Process publish(PublishArgs(domain, dataset, "50"), test::TempPath("publish_second_signal.log"));
  ASSERT_EQ(publish.wait(120s), 0) << test::ReadFile(test::TempPath("publish_second_signal.log"));
  ASSERT_TRUE(listener.waitFor(2, 120s)) << listener.summary();
  serve.signal(SIGTERM);
  std::this_thread::sleep_for(200ms);
  serve.signal(SIGTERM);
  ASSERT_EQ(serve.wait(120s), 0) << test::ReadFile(log);
  const std::string text = test::ReadFile(log);
  const size_t at = text.find(" frames, results written to");
  ASSERT_NE(at, std::string::npos) << text;
  const size_t start = text.rfind(' ', at - 1) + 1;
  const int processed = std::stoi(text.substr(start, at - start));
  EXPECT_GE(processed, 2) << text;
  EXPECT_LT(processed, 100) << text;  // the backlog was dropped, not worked through
  // The status lines show the drops, and the count of processed frames moves while the batch is worked on.
  std::set<std::string> processed_counts;
  for (size_t p = text.find("frames processed"); p != std::string::npos; p = text.find("frames processed", p + 1)) {
    const size_t begin = text.rfind(", ", p) + 2;
    processed_counts.insert(text.substr(begin, p - begin));
    EXPECT_NE(text.find("dropped (backlog full)", p), std::string::npos);
  }
  EXPECT_NE(text.find("latency ms (median/p99): input "), std::string::npos) << text;
  EXPECT_GE(processed_counts.size(), 2u) << text;
  // What was estimated is on disk, whole: one pose per processed frame.
  std::ifstream tum(out + "/default/camera_ours.tum");
  int lines = 0;
  for (std::string line; std::getline(tum, line);) lines += !line.empty() && line[0] != '#';
  EXPECT_EQ(lines, processed);
}

// By default, when serve falls behind the newest frame wins: frames are dropped before the front-end
// (counted, their odometry carried on) instead of waiting, so that the time from a frame's arrival to
// its estimate stays within a few stage times however far behind serve is.
TEST(ServeLoopback, WhenItFallsBehindTheNewestFrameWinsAndTheDelayStaysBounded) {
  const std::string dataset = CityDataset(100, 1);
  const int domain = test::DomainFor(test::DdsTestSlot::kLoopbackNewestWins);
  const std::string out = test::TempPath("serve_newest_out");
  const std::string log = test::TempPath("serve_newest.log");
  std::vector<std::string> args = ServeArgs(domain, dataset, out);
  args.erase(std::find(args.begin(), args.end(), "--every-frame"));
  const std::string slow = test::TempPath("slow_backend_newest.yaml");  // as in the test above: far behind
  std::ofstream(slow) << "backend:\n  schedule: window:40\n  object_window_frames: 40\n";
  args.insert(args.end(), {"--config", slow});
  test::Process serve(args, log);
  Listener listener(domain, "");
  test::Process publish(PublishArgs(domain, dataset, "50"), test::TempPath("publish_newest.log"));
  ASSERT_EQ(publish.wait(120s), 0) << test::ReadFile(test::TempPath("publish_newest.log"));
  std::this_thread::sleep_for(3s);  // the frames in progress finish
  serve.signal(SIGTERM);
  ASSERT_EQ(serve.wait(120s), 0) << test::ReadFile(log);

  std::ifstream metrics_file(out + "/default/metrics.json");
  ASSERT_TRUE(metrics_file) << test::ReadFile(log);
  const nlohmann::json run = nlohmann::json::parse(metrics_file)["run"];
  const int processed = run["frames"].get<int>();
  EXPECT_EQ(run["frames_assembled"].get<int>(), 100) << run.dump();
  EXPECT_LT(processed, 100) << "serve kept up: the test proves nothing";
  EXPECT_GE(processed, 5);
  EXPECT_EQ(run["dropped_queue_full"].get<int>(), 100 - processed) << run.dump();  // every drop counted
  EXPECT_EQ(run["frames_missing"].get<int>(), 0) << run.dump();  // dropped here, not lost on the way
  // A frame waits for at most the frame before it in each stage.
  const nlohmann::json& latency = run["latency_ms"];
  const double frontend_max = latency["frontend"]["max_ms"].get<double>();
  const double backend_max = latency["backend"]["max_ms"].get<double>();
  const double slack_ms = 100.0;  // thread wake-ups and the publisher's bursts on a loaded machine
  EXPECT_LE(latency["frontend_wait"]["max_ms"].get<double>(), frontend_max + backend_max + slack_ms) << latency.dump();
  EXPECT_LE(latency["backend_wait"]["max_ms"].get<double>(), 2.0 * backend_max + slack_ms) << latency.dump();
  // The dropped frames' odometry went on into the next frame's: the camera stays on the reference path.
  std::vector<int64_t> t_ns;
  const std::vector<SE3> estimated = ReadTumTrajectory(out + "/default/camera_ours.tum", &t_ns);
  ASSERT_EQ(static_cast<int>(estimated.size()), processed);
  std::map<int64_t, Vec3> reference;
  for (const FrameEstimate& e : test::ServeReference(dataset)) reference[e.t_ns] = e.T_world_camera.translation();
  double worst_m = 0.0;
  for (size_t k = 0; k < estimated.size(); ++k) {
    ASSERT_TRUE(reference.count(t_ns[k])) << t_ns[k];
    worst_m = std::max(worst_m, (estimated[k].translation() - reference[t_ns[k]]).norm());
  }
  // Against the distance the reference travels meanwhile: odometry lost with the dropped frames (about three
  // in four here) would leave the camera short by most of it. What remains is the odometry's own drift over
  // the gaps: 0.03-0.26 m of 59 m in 12 runs on a loaded machine. (Before the front-end stopped handing on
  // unverified static tracks after a gap and the back-end stopped tying motions of unequal steps, a run in
  // CI ended 9 m off, and a bound of 15 % failed; tests/pipeline/dropped_frames_test.cpp replays such runs.)
  double path_m = 0.0;
  for (auto it = reference.find(t_ns.front()); it != reference.end() && std::next(it) != reference.end() &&
                                               it->first < t_ns.back();
       ++it)
    path_m += (std::next(it)->second - it->second).norm();
  EXPECT_GT(path_m, 10.0);
  EXPECT_LT(worst_m, 0.03 * path_m) << "path " << path_m << " m";
}

TEST(ServeLoopback, SigkillLeavesEveryFrameThatLeftTheWindowOnDisk) {
  const std::string dataset = CityDataset(30, 1);
  const int domain = test::DomainFor(test::DdsTestSlot::kLoopbackSigkill);
  const std::string out = test::TempPath("serve_kill_out");
  test::Process serve(ServeArgs(domain, dataset, out), test::TempPath("serve_kill.log"));
  Listener listener(domain, "");
  test::Process publish(PublishArgs(domain, dataset, "10"), test::TempPath("publish_kill.log"));
  ASSERT_TRUE(listener.waitFor(20, 120s)) << listener.summary();
  serve.signal(SIGKILL);  // no handler runs: only what was streamed is there
  serve.wait(30s);
  std::vector<int64_t> t_ns;
  const std::vector<SE3> streamed = ReadTumTrajectory(out + "/default/camera_ours.tum", &t_ns);
  MethodResult full;
  const std::vector<FrameEstimate> online = test::ServeReference(dataset, &full);
  // At least the frames that left the window (10 frames) of the 20 estimated, each equal to the final pose
  // of an uninterrupted run (to the 1e-9 m of the file's fixed 9 decimals).
  ASSERT_GE(streamed.size(), 10u);
  ASSERT_LT(streamed.size(), 30u);
  for (size_t k = 0; k < streamed.size(); ++k) {
    EXPECT_EQ(t_ns[k] / 1000, online[k].t_ns / 1000) << k;
    EXPECT_LT((streamed[k].translation() - full.estimate.T_world_camera[k].translation()).norm(), 2e-9) << k;
  }
  EXPECT_GE(ReadTumTrajectory(out + "/default/camera_ours_online.tum").size(), 20u);
}

TEST(ServeLoopback, BadSamplesAreRejectedAndCountedAndServeKeepsRunning) {
  const std::string dataset = CityDataset(12, 1);
  const int domain = test::DomainFor(test::DdsTestSlot::kLoopbackBadSamples);
  test::Process serve(ServeArgs(domain, dataset, test::TempPath("serve_bad_out"), "1000"),
                      test::TempPath("serve_bad.log"));
  Listener listener(domain, "");
  {
    DdsSession session(domain, LosslessProfiles());
    const VehicleTopics t = TopicsFor("");
    auto* colour = session.writer(t.colour, new sensor_msgs::msg::ImagePubSubType(), "sensor_writer");
    auto* mask = session.writer(t.mask, new sensor_msgs::msg::ImagePubSubType(), "sensor_writer");
    auto* odometry = session.writer(t.odometry, new nav_msgs::msg::OdometryPubSubType(), "sensor_writer");
    for (int i = 0; i < 100; ++i) {  // until serve's readers are matched
      dds::PublicationMatchedStatus matched;
      odometry->get_publication_matched_status(matched);
      if (matched.current_count > 0) break;
      std::this_thread::sleep_for(50ms);
    }
    const cv::Mat image(375, 1242, CV_8UC3, cv::Scalar(50));
    auto short_data = EncodeImage(image, ImageRole::kColour, 1'000'000'000, "c");
    short_data.data().resize(1000);
    colour->write(&short_data);
    auto unknown = EncodeImage(image, ImageRole::kColour, 1'100'000'000, "c");
    unknown.encoding("yuv422");
    colour->write(&unknown);
    auto not_a_mask = EncodeImage(image, ImageRole::kColour, 1'200'000'000, "c");  // bgr8 on the mask topic
    mask->write(&not_a_mask);
    auto nan_odometry = EncodeOdometry(SE3(), 1'300'000'000, "o", "c");
    nan_odometry.pose().pose().position().y(std::nan(""));
    odometry->write(&nan_odometry);
    auto lone_colour = EncodeImage(image, ImageRole::kColour, 1'400'000'000, "c");  // nothing else comes
    colour->write(&lone_colour);
    // No newer stamp follows: the set is dropped once the stream has been silent for --silence-ms, and
    // serve reports it although no frame is processed.
    const bool reported = listener.waitUntil(
        [&] {
          return !listener.statuses.empty() && listener.statuses.back().dropped_incomplete() == 1u &&
                 listener.statuses.back().rejected_invalid() >= 4u;
        },
        30s);
    EXPECT_TRUE(reported) << listener.summary();
  }
  // Then a good replay: serve is still there and processes it.
  test::Process publish(PublishArgs(domain, dataset, "10"), test::TempPath("publish_bad.log"));
  ASSERT_EQ(publish.wait(60s), 0);
  ASSERT_TRUE(listener.waitFor(12, 120s)) << listener.summary();
  EXPECT_TRUE(serve.running());
  ASSERT_TRUE(listener.waitForStatusAfter(12, 30s)) << listener.summary();
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    EXPECT_EQ(listener.statuses.back().frames_processed(), 12u);
    EXPECT_GE(listener.statuses.back().rejected_invalid(), 4u);
  }
  serve.signal(SIGTERM);
  EXPECT_EQ(serve.wait(60s), 0);
}

// A camera driver on a network that loses messages (Fast DDS' test UDP transport drops half of its data
// messages; no shared memory): serve's best-effort readers see gaps in the writer's sequence numbers and
// the status counts the samples lost, which the other counters cannot show (those samples never arrive).
TEST(ServeLoopback, SamplesLostOnTheNetworkAreCountedInTheStatus) {
  const std::string dataset = CityDataset(12, 1);
  const int domain = test::DomainFor(test::DdsTestSlot::kLoopbackSamplesLost);
  std::vector<std::string> args = ServeArgs(domain, dataset, test::TempPath("serve_lost_out"));
  *std::next(std::find(args.begin(), args.end(), "--profiles")) = kProfiles;  // best-effort sensor readers
  test::Process serve(args, test::TempPath("serve_lost.log"));
  Listener listener(domain, "");

  dds::DomainParticipantQos qos;
  qos.transport().use_builtin_transports = false;
  auto lossy = std::make_shared<eprosima::fastdds::rtps::test_UDPv4TransportDescriptor>();
  lossy->dropDataMessagesPercentage = 50;
  qos.transport().user_transports.push_back(lossy);
  auto* factory = dds::DomainParticipantFactory::get_instance();
  dds::DomainParticipant* participant = factory->create_participant(domain, qos);
  ASSERT_NE(participant, nullptr);
  dds::TypeSupport type(new nav_msgs::msg::OdometryPubSubType());
  type.register_type(participant);
  dds::Topic* topic = participant->create_topic(TopicsFor("").odometry, type.get_type_name(), dds::TOPIC_QOS_DEFAULT);
  dds::Publisher* publisher = participant->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
  dds::DataWriterQos writer_qos = dds::DATAWRITER_QOS_DEFAULT;
  writer_qos.reliability().kind = dds::BEST_EFFORT_RELIABILITY_QOS;  // a camera driver's sensor-data QoS
  writer_qos.history().depth = 5;
  dds::DataWriter* writer = publisher->create_datawriter(topic, writer_qos);
  ASSERT_NE(writer, nullptr);
  for (int i = 0; i < 600; ++i) {  // discovery goes through the lossy transport too: it takes retries
    dds::PublicationMatchedStatus matched;
    writer->get_publication_matched_status(matched);
    if (matched.current_count > 0) break;
    std::this_thread::sleep_for(50ms);
  }
  constexpr int kSamples = 60;
  for (int i = 0; i < kSamples; ++i) {
    auto odometry = EncodeOdometry(SE3(), 1'000'000'000 + 100'000'000LL * i, "o", "c");
    writer->write(&odometry);
    std::this_thread::sleep_for(10ms);
  }
  const bool counted = listener.waitUntil(
      [&] { return !listener.statuses.empty() && listener.statuses.back().samples_lost() >= 5u; }, 30s);
  EXPECT_TRUE(counted) << listener.summary();
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    if (!listener.statuses.empty()) {
      const auto& status = listener.statuses.back();
      EXPECT_LE(status.frames_received() + status.samples_lost(), static_cast<uint64_t>(kSamples));
      EXPECT_GT(status.frames_received(), 0u);
    }
  }
  participant->delete_contained_entities();
  factory->delete_participant(participant);
  serve.signal(SIGTERM);
  EXPECT_EQ(serve.wait(60s), 0);
}

TEST(ServeLoopback, APublisherRestartedMidSequenceIsFollowedAndTwoVehiclesStaySeparate) {
  const std::string city_a = CityDataset(16, 1), city_b = CityDataset(16, 2);
  const int domain = test::DomainFor(test::DdsTestSlot::kLoopbackRestart);
  auto args = ServeArgs(domain, city_a, test::TempPath("serve_two_out"));
  for (const char* v : {"--vehicle", "a", "--vehicle", "b"}) args.push_back(v);
  test::Process serve(args, test::TempPath("serve_two.log"));
  Listener a(domain, "a"), b(domain, "b");
  // The publishers reach serve over UDP: a process killed while it writes into serve's shared-memory port
  // can leave that port stuck in Fast DDS 2.9, after which serve hears no participant of this host over
  // shared memory (a known Fast DDS problem, seen once here as a restarted publisher never matching).
  auto publish_args = [&](const std::string& dataset, const std::string& vehicle, int start, int frames) {
    auto p = PublishArgs(domain, dataset, "5", LosslessUdpProfiles());
    for (const std::string& s : {std::string("--vehicle"), vehicle, std::string("--start-frame"), std::to_string(start),
                                 std::string("--frames"), std::to_string(frames)})
      p.push_back(s);
    return p;
  };
  {
    // Vehicle a's publisher is killed mid-sequence; a new one resumes after the last estimate received.
    // Frames serve had already assembled come again and are rejected as stamps going backwards.
    test::Process first(publish_args(city_a, "a", 0, 16), test::TempPath("pub_a1.log"));
    test::Process other(publish_args(city_b, "b", 0, 16), test::TempPath("pub_b.log"));
    ASSERT_TRUE(a.waitFor(5, 60s)) << a.summary();
    first.signal(SIGKILL);
    first.wait(10s);
    int resume = 0;
    {
      std::lock_guard<std::mutex> lock(a.mutex);
      resume = static_cast<int>(a.poses_by_stamp.size());
    }
    ASSERT_LT(resume, 16) << "the first publisher finished before it could be killed";
    test::Process second(publish_args(city_a, "a", resume, 16 - resume), test::TempPath("pub_a2.log"));
    ASSERT_EQ(second.wait(90s), 0) << test::ReadFile(test::TempPath("pub_a2.log"));
    ASSERT_EQ(other.wait(60s), 0) << test::ReadFile(test::TempPath("pub_b.log"));
  }
  ASSERT_NO_FATAL_FAILURE(ExpectBothEqualTheirReferences(a, city_a, b, city_b, 16))
      << "second publisher:\n" << test::ReadFile(test::TempPath("pub_a2.log"));
  serve.signal(SIGINT);
  EXPECT_EQ(serve.wait(60s), 0);
  EXPECT_TRUE(fs::exists(test::TempPath("serve_two_out") + "/a/camera_ours.tum"));
  EXPECT_TRUE(fs::exists(test::TempPath("serve_two_out") + "/b/camera_ours.tum"));
}

TEST(ServeLoopback, AFleetSharedByTwoServesHasEachVehicleServedOnce) {
  // A fleet spread over participants (here processes; hosts work the same through discovery): both serves
  // are given the whole fleet, each its place among the two (--fleet-share), and each follows only its share.
  const std::string city_a = CityDataset(10, 1), city_b = CityDataset(10, 2);
  const int domain = test::DomainFor(test::DdsTestSlot::kLoopbackTwoProcesses);
  const std::string out_a = test::TempPath("serve_a_out"), out_b = test::TempPath("serve_b_out");
  auto serve_args = [&](const std::string& out, const std::string& share) {
    auto args = ServeArgs(domain, city_a, out);
    for (const char* v : {"b", "a"}) args.push_back("--vehicle"), args.push_back(v);
    args.push_back("--fleet-share"), args.push_back(share);
    return args;
  };
  test::Process serve_a(serve_args(out_a, "0/2"), test::TempPath("serve_a.log"));
  test::Process serve_b(serve_args(out_b, "1/2"), test::TempPath("serve_b.log"));
  Listener a(domain, "a"), b(domain, "b");
  auto publish_args = [&](const std::string& dataset, const std::string& vehicle) {
    auto p = PublishArgs(domain, dataset, "5");
    p.push_back("--vehicle"), p.push_back(vehicle);
    return p;
  };
  test::Process publish_a(publish_args(city_a, "a"), test::TempPath("pub_sep_a.log"));
  // Vehicle b's frames are all encoded before the first is sent (--preload): the same messages, stamps and
  // estimates as sending each as it is read.
  auto preloaded = publish_args(city_b, "b");
  preloaded.push_back("--preload");
  test::Process publish_b(preloaded, test::TempPath("pub_sep_b.log"));
  ASSERT_EQ(publish_a.wait(60s), 0);
  ASSERT_EQ(publish_b.wait(60s), 0);
  EXPECT_NE(test::ReadFile(test::TempPath("pub_sep_b.log")).find("10 frames encoded before sending"), std::string::npos);
  ASSERT_NO_FATAL_FAILURE(ExpectBothEqualTheirReferences(a, city_a, b, city_b, 10));
  ASSERT_TRUE(a.waitForStatusAfter(10, 30s)) << a.summary();
  ASSERT_TRUE(b.waitForStatusAfter(10, 30s)) << b.summary();
  {
    // Each process counted only its own vehicle's samples: four per frame; each estimate came once.
    std::lock_guard<std::mutex> lock_a(a.mutex), lock_b(b.mutex);
    EXPECT_EQ(a.statuses.back().vehicle(), "a");
    EXPECT_EQ(b.statuses.back().vehicle(), "b");
    EXPECT_EQ(a.statuses.back().frames_received(), 40u);
    EXPECT_EQ(b.statuses.back().frames_received(), 40u);
    EXPECT_EQ(a.odometry_samples, 10u);
    EXPECT_EQ(b.odometry_samples, 10u);
  }
  serve_a.signal(SIGTERM);
  serve_b.signal(SIGTERM);
  EXPECT_EQ(serve_a.wait(60s), 0);
  EXPECT_EQ(serve_b.wait(60s), 0);
  EXPECT_TRUE(fs::exists(out_a + "/a/camera_ours.tum"));
  EXPECT_FALSE(fs::exists(out_a + "/b"));
  EXPECT_TRUE(fs::exists(out_b + "/b/camera_ours.tum"));
  EXPECT_FALSE(fs::exists(out_b + "/a"));
}

// Two serves given the same vehicle by mistake (shared ownership: subscribers would take both streams): the
// one of the higher participant GUID goes quiet, so every estimate reaches the subscriber once; it keeps
// estimating, and publishes when the other leaves.
TEST(ServeLoopback, AVehicleGivenToTwoServesIsPublishedByOneAndTheOtherTakesOverWhenItLeaves) {
  const std::string city = CityDataset(10, 1);
  const int domain = test::DomainFor(test::DdsTestSlot::kLoopbackQuiet);
  const std::string out_1 = test::TempPath("serve_quiet_1"), out_2 = test::TempPath("serve_quiet_2");
  const std::string log_1 = test::TempPath("serve_quiet_1.log"), log_2 = test::TempPath("serve_quiet_2.log");
  auto serve_args = [&](const std::string& out) {
    auto args = ServeArgs(domain, city, out);
    args.push_back("--vehicle"), args.push_back("a");
    return args;
  };
  auto serve_1 = std::make_unique<test::Process>(serve_args(out_1), log_1);
  auto serve_2 = std::make_unique<test::Process>(serve_args(out_2), log_2);
  const std::string quiet = "this one goes quiet";
  bool one_quiet = false;
  for (int i = 0; i < 600 && !one_quiet; ++i) {
    std::this_thread::sleep_for(50ms);
    one_quiet = test::ReadFile(log_1).find(quiet) != std::string::npos ||
                test::ReadFile(log_2).find(quiet) != std::string::npos;
  }
  ASSERT_TRUE(one_quiet) << test::ReadFile(log_1) << test::ReadFile(log_2);
  const bool first_is_quiet = test::ReadFile(log_1).find(quiet) != std::string::npos;
  EXPECT_NE(first_is_quiet, test::ReadFile(log_2).find(quiet) != std::string::npos) << "exactly one goes quiet";
  Listener listener(domain, "a");
  auto publish_args = PublishArgs(domain, city, "5");
  // Stamped when sent, so that the second replay below goes on where the first ended.
  for (const char* arg : {"--vehicle", "a", "--stamp-now"}) publish_args.push_back(arg);
  test::Process publish(publish_args, test::TempPath("pub_quiet.log"));
  ASSERT_EQ(publish.wait(60s), 0);
  ASSERT_TRUE(listener.waitFor(10, 60s)) << listener.summary();
  ASSERT_TRUE(listener.waitForStatusAfter(10, 30s)) << listener.summary();
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    EXPECT_EQ(listener.odometry_samples, 10u);  // once each
  }
  // The publishing one leaves: the quiet one says it publishes again, and its estimates reach the subscriber.
  std::unique_ptr<test::Process>& publishing = first_is_quiet ? serve_2 : serve_1;
  std::unique_ptr<test::Process>& quiet_one = first_is_quiet ? serve_1 : serve_2;
  const std::string& quiet_log = first_is_quiet ? log_1 : log_2;
  publishing->signal(SIGTERM);
  EXPECT_EQ(publishing->wait(60s), 0);
  ASSERT_TRUE(test::WaitForLogLine(quiet_log, "publishes again", 30s)) << test::ReadFile(quiet_log);
  test::Process replay(publish_args, test::TempPath("pub_quiet_again.log"));
  ASSERT_EQ(replay.wait(60s), 0);
  ASSERT_TRUE(listener.waitUntil([&] { return listener.odometry_samples >= 20; }, 60s)) << listener.summary();
  quiet_one->signal(SIGTERM);
  EXPECT_EQ(quiet_one->wait(60s), 0);
  // The quiet one estimated every frame all along and wrote its results; it counted what it did not publish.
  const nlohmann::json run = test::ReadJsonObject((first_is_quiet ? out_1 : out_2) + "/a/metrics.json")["run"];
  EXPECT_EQ(run.value("frames", 0), 20) << run.dump();
  EXPECT_EQ(run.value("frames_not_published", 0), 10) << run.dump();
  {
    std::lock_guard<std::mutex> lock(listener.mutex);
    EXPECT_EQ(listener.odometry_samples, 20u);
  }
}

// The odometry's velocity uncertainty (twist covariance) is the increment's sigma over the time the increment
// spans in the dataset, also when the frames are stamped as they are sent: stamped with the send time, the
// span was taken from the dataset's previous stamp to now (about 1.8e9 s), which told serve the odometry was
// exact.
TEST(ServeLoopback, OdometryStampedWhenSentCarriesTheIncrementsOwnVelocitySigma) {
  const std::string city = CityDataset(10, 1);
  const int domain = test::DomainFor(test::DdsTestSlot::kPublishTwist);
  struct OdometryReader : dds::DataReaderListener {
    void on_data_available(dds::DataReader* reader) override {
      nav_msgs::msg::Odometry msg;
      dds::SampleInfo info;
      while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        std::string error;
        const auto pose = DecodeOdometry(msg, &error);
        std::lock_guard<std::mutex> lock(mutex);
        if (pose) twist_sigmas.push_back(pose->twist_sigma_per_s);
      }
    }
    std::mutex mutex;
    std::vector<std::optional<Vec6>> twist_sigmas;
  } odometry;
  DdsSession session(domain, LosslessProfiles());
  session.reader(TopicsFor("").odometry, new nav_msgs::msg::OdometryPubSubType(), "sensor_reader", &odometry);
  // Readers of the images too, so that publish finds a reader of every input topic and starts at once.
  for (const std::string& topic : {TopicsFor("").colour, TopicsFor("").depth, TopicsFor("").mask})
    session.reader(topic, new sensor_msgs::msg::ImagePubSubType(), "sensor_reader", nullptr);
  auto args = PublishArgs(domain, city, "10");
  args.push_back("--stamp-now");
  test::Process publish(args, test::TempPath("pub_twist.log"));
  ASSERT_EQ(publish.wait(60s), 0) << test::ReadFile(test::TempPath("pub_twist.log"));
  const ImageDataset dataset(city, ImageDatasetOptions{});
  for (int i = 0; i < 100; ++i) {
    {
      std::lock_guard<std::mutex> lock(odometry.mutex);
      if (odometry.twist_sigmas.size() >= 10) break;
    }
    std::this_thread::sleep_for(50ms);
  }
  std::lock_guard<std::mutex> lock(odometry.mutex);
  ASSERT_EQ(odometry.twist_sigmas.size(), 10u);
  int checked = 0;
  for (int k = 1; k < 10; ++k) {
    const auto increment = dataset.odometryAt(k);
    ASSERT_TRUE(increment);
    const double dt_s = 1e-9 * static_cast<double>(dataset.stampNs(k) - dataset.stampNs(k - 1));
    ASSERT_TRUE(odometry.twist_sigmas[static_cast<size_t>(k)]) << k;
    const Vec6 expected = increment->sigma / dt_s;
    EXPECT_LT((*odometry.twist_sigmas[static_cast<size_t>(k)] - expected).norm(), 1e-9 * expected.norm()) << k;
    ++checked;
  }
  EXPECT_EQ(checked, 9);
}

}  // namespace
}  // namespace dslam
