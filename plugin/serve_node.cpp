#include "plugin/serve_node.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "dslam_msgsPubSubTypes.h"
#include "nav_msgs_OdometryPubSubTypes.h"
#include "output/dir_lock.h"
#include "output/run_report.h"
#include "output/trajectory_io.h"
#include "output/whole_file.h"
#include "plugin/compressed_image.h"
#include "plugin/dds_session.h"
#include "plugin/fleet_share.h"
#include "plugin/image_message.h"
#include "plugin/object_markers.h"
#include "plugin/point_cloud_message.h"
#include "plugin/ros_distro.h"
#include "plugin/ros_graph.h"
#include "plugin/topics.h"
#include "pipeline/bounded_queue.h"
#include "pipeline/mask_source.h"
#include "pipeline/stage_latency.h"
#include "pipeline/staged_pipeline.h"
#include "sensor_msgs_CompressedImagePubSubTypes.h"
#include "sensor_msgs_ImagePubSubTypes.h"
#include "sensor_msgs_PointCloud2PubSubTypes.h"
#include "visualization_msgs_MarkerArrayPubSubTypes.h"

namespace dslam {
namespace dds = eprosima::fastdds::dds;
using Clock = std::chrono::steady_clock;

namespace {

dslam_msgs::msg::ObjectMotionArray ToMessage(const FrameEstimate& e, double frame_rate_hz) {
  dslam_msgs::msg::ObjectMotionArray msg;
  msg.header().stamp(NsToStamp(e.t_ns));
  msg.header().frame_id("world");
  for (const ObjectMotionEstimate& m : e.object_motions) {
    dslam_msgs::msg::ObjectMotion o;
    o.object_id(m.object_id);
    const Vec3& t = m.H_world.translation();
    const Eigen::Quaterniond& q = m.H_world.rotation();
    o.h_world().position().x(t.x()), o.h_world().position().y(t.y()), o.h_world().position().z(t.z());
    o.h_world().orientation().x(q.x()), o.h_world().orientation().y(q.y());
    o.h_world().orientation().z(q.z()), o.h_world().orientation().w(q.w());
    const Vec3 v = m.velocityMps(frame_rate_hz);
    o.velocity_mps().x(v.x()), o.velocity_mps().y(v.y()), o.velocity_mps().z(v.z());
    o.speed_mps(m.speed_mps);
    const Vec3 centroid_world = m.centroidWorld();
    o.centroid_world().x(centroid_world.x()), o.centroid_world().y(centroid_world.y());
    o.centroid_world().z(centroid_world.z());
    o.is_dynamic(m.is_dynamic);
    for (int i = 0; i < 36; ++i) o.covariance()[i] = m.covariance(i / 6, i % 6);  // row-major
    o.centroid_camera().x(m.centroid_camera.x()), o.centroid_camera().y(m.centroid_camera.y());
    o.centroid_camera().z(m.centroid_camera.z());
    if (m.image_box) {
      o.box_x(m.image_box->x), o.box_y(m.image_box->y);
      o.box_width(m.image_box->width), o.box_height(m.image_box->height);
    }
    msg.objects().push_back(o);
  }
  return msg;
}

}  // namespace

// One vehicle, four threads: Fast DDS' receive thread only copies each sample into the inbox (never
// waiting: when the inbox is full the oldest sample is dropped and counted); the intake thread decodes
// samples and assembles frames; the feeder hands assembled frames to the staged pipeline, whose front-end
// and back-end threads run in parallel; the back-end thread publishes each estimate.
class Vehicle {
 public:
  Vehicle(DdsSession& session, const std::string& name, const ServeOptions& options, const RunConfig& config)
      : name_(name),
        options_(options),
        masks_(MaskSourceOf(config)),
        assembler_(options.assembler),
        inbox_(kInboxSamplesPerFrame * static_cast<size_t>(options.assembler.max_pending)),
        dir_lock_(ResultDir(options, name)),
        stream_(ResultDir(options, name)),
        colour_listener_(this, ImageSample(ImageRole::kColour), &Sample::image),
        depth_listener_(this, ImageSample(ImageRole::kDepth), &Sample::image),
        mask_listener_(this, ImageSample(ImageRole::kMask), &Sample::image),
        colour_compressed_listener_(this, ImageSample(ImageRole::kColour, true), &Sample::compressed),
        depth_compressed_listener_(this, ImageSample(ImageRole::kDepth, true), &Sample::compressed),
        mask_compressed_listener_(this, ImageSample(ImageRole::kMask, true), &Sample::compressed),
        lidar_listener_(this, LidarSample(), &Sample::cloud),
        odometry_listener_(this, Sample{}, &Sample::odometry) {
    const VehicleTopics topics = TopicsFor(name);
    // Every output carries the instance's ownership strength: with EXCLUSIVE ownership a subscriber follows
    // one serve for all of them, the status included.
    dds::DataWriterQos estimate_qos = session.writerQos("estimate_writer");
    if (options.ownership_strength) {
      if (estimate_qos.ownership().kind != dds::EXCLUSIVE_OWNERSHIP_QOS)
        throw std::invalid_argument("--ownership-strength has no effect with " + options.profiles_file +
                                    ": its estimate_writer's ownership is SHARED (a hot standby needs EXCLUSIVE, as in "
                                    "config/dds_profiles_hot_standby.xml)");
      estimate_qos.ownership_strength().value = *options.ownership_strength;
    }
    estimate_qos_ = estimate_qos;
    odometry_writer_ = session.writer(topics.camera_odometry, new nav_msgs::msg::OdometryPubSubType(), estimate_qos);
    objects_writer_ =
        session.writer(topics.object_motions, new dslam_msgs::msg::ObjectMotionArrayPubSubType(), estimate_qos);
    status_writer_ = session.writer(topics.status, new dslam_msgs::msg::StatusPubSubType(), estimate_qos);
    markers_writer_ = session.writer(topics.markers, new visualization_msgs::msg::MarkerArrayPubSubType(), estimate_qos);
    StagedPipelineCallbacks callbacks;
    callbacks.on_estimate = [this](const FrameEstimate& e, const FrameMeasurement&, const FrameTiming& timing) {
      publish(e, timing);
    };
    callbacks.on_rejected = [this](const ImageFrame& frame, const std::string& reason) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        assembler_.reject(std::string("frame at ") + std::to_string(frame.t_ns) + " ns: " + reason);
        handed_at_.erase(frame.t_ns);
      }
      wake_.notify_one();  // the feeder reports the rejection
    };
    // Newest wins: one frame waits before each stage, so that an estimate lags its image by at most the
    // frames in progress; every frame: up to --max-pending wait.
    const size_t queue_capacity = options.every_frame ? static_cast<size_t>(options.assembler.max_pending) : 1;
    pipeline_ = std::make_unique<StagedPipeline>(config, options.camera, options.frame_rate_hz, queue_capacity, callbacks,
                                                 &stream_, /*collect=*/false);
    // Readers first: when one cannot be created (a missing profile, security denying the topic) the
    // constructor throws before any thread of ours runs. Samples that arrive meanwhile wait in the inbox.
    std::vector<dds::DataReader*> readers;
    try {
      readers.push_back(
          session.reader(topics.colour, new sensor_msgs::msg::ImagePubSubType(), "sensor_reader", &colour_listener_));
      readers.push_back(
          session.reader(topics.depth, new sensor_msgs::msg::ImagePubSubType(), "sensor_reader", &depth_listener_));
      readers.push_back(
          session.reader(topics.mask, new sensor_msgs::msg::ImagePubSubType(), "sensor_reader", &mask_listener_));
      // A driver may send any image compressed instead (image_transport's "compressed"): both forms are read.
      readers.push_back(session.reader(topics.colour_compressed, new sensor_msgs::msg::CompressedImagePubSubType(),
                                       "sensor_reader", &colour_compressed_listener_));
      readers.push_back(session.reader(topics.depth_compressed, new sensor_msgs::msg::CompressedImagePubSubType(),
                                       "sensor_reader", &depth_compressed_listener_));
      readers.push_back(session.reader(topics.mask_compressed, new sensor_msgs::msg::CompressedImagePubSubType(),
                                       "sensor_reader", &mask_compressed_listener_));
      readers.push_back(
          session.reader(topics.odometry, new nav_msgs::msg::OdometryPubSubType(), "sensor_reader", &odometry_listener_));
      if (masks_.source == MaskSourceKind::kLidarClusters)
        readers.push_back(session.reader(topics.lidar, new sensor_msgs::msg::PointCloud2PubSubType(), "sensor_reader",
                                         &lidar_listener_));
    } catch (...) {
      for (dds::DataReader* r : readers) r->set_listener(nullptr);  // they outlive this half-built vehicle
      throw;
    }
    graph_node_.node_namespace = "/" + name;
    graph_node_.node_name = options.node_name;
    for (dds::DataReader* r : readers) graph_node_.reader_gids.push_back(ToRosGid(r->guid()));
    for (dds::DataWriter* w : {odometry_writer_, objects_writer_, status_writer_, markers_writer_})
      graph_node_.writer_gids.push_back(ToRosGid(w->guid()));
    intake_ = std::thread([this] { runIntake(); });
    feeder_ = std::thread([this] { runFeeder(); });
  }

  ~Vehicle() { stop(); }

  // Stops taking samples and finishes every frame already assembled (their estimates are published:
  // call it while the session's writers exist). Idempotent.
  void stop() {
    inbox_.close();
    if (intake_.joinable()) intake_.join();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (feeder_.joinable()) feeder_.join();
    if (!result_ && pipeline_failure_.empty()) {
      try {
        result_ = pipeline_->finish();
      } catch (const std::exception& e) {
        pipeline_failure_ = e.what();
      }
    }
  }

  // From any thread, also while stop() waits: drop the backlog (inbox, assembled sets, the pipeline's
  // queues); the frame in progress completes and what was estimated is flushed as on a normal stop.
  void abandonBacklog() {
    abandon_ = true;
    pipeline_->skipQueued();
    wake_.notify_all();
  }

  // Returns when every matched reliable reader has acknowledged what the writers sent, at most 2 s a writer.
  void waitForAcknowledgments() {
    for (dds::DataWriter* w : {odometry_writer_, objects_writer_, status_writer_, markers_writer_})
      w->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(2, 0));
  }

  // Readers matched by the camera estimates' writer. Only while the session exists (the writer is its).
  int estimateReaders() const {
    dds::PublicationMatchedStatus matched;
    if (odometry_writer_->get_publication_matched_status(matched) != eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK)
      return 0;
    return matched.current_count;
  }

  // This vehicle's ROS 2 node: its namespace, name, readers and writers.
  const RosGraphNode& graphNode() const { return graph_node_; }

  // The QoS of the estimates' writers (the profile's, with --ownership-strength).
  const dds::DataWriterQos& estimateQos() const { return estimate_qos_; }

  // From Fast DDS' discovery thread (RivalWriterWatch): `other` is the participant it yields to, "" to publish.
  void setQuiet(const std::string& other) {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.quiet = !other.empty();
    status_.quiet_for = other;
    quiet_ = status_.quiet;
  }

  VehicleStatus status() const {
    std::lock_guard<std::mutex> lock(mutex_);
    VehicleStatus s = status_;
    s.counters = countersLocked();
    s.latency = latency_.summary();
    return s;
  }

  // The estimates are on disk already (streamed as they became final; the last window was flushed by
  // stop()): this adds the KITTI-format trajectory and metrics.json with the session's counters. Nothing
  // of the session is kept in memory for it, so a service can run for hours.
  void writeResults(std::ostream& log) {
    const std::string dir = ResultDir(options_, name_);
    stop();
    if (!pipeline_failure_.empty()) log << "vehicle '" << name_ << "': the pipeline failed: " << pipeline_failure_ << std::endl;
    const int frames = static_cast<int>(frames_processed_);
    if (frames == 0 || !result_) {
      log << "vehicle '" << name_ << "': no frame processed, nothing written" << std::endl;
      return;
    }
    nlohmann::json info;
    info["command"] = "serve";
    info["vehicle"] = name_;
    info["frames"] = frames;
    const VehicleStatus s = status();
    info["frames_received"] = s.counters.parts_received;
    info["frames_assembled"] = s.counters.frames_assembled;
    info["dropped_incomplete"] = s.counters.dropped_incomplete;
    info["frames_missing"] = s.counters.frames_missing;
    info["dropped_queue_full"] = s.counters.dropped_queue_full;
    info["rejected_invalid"] = s.counters.rejected_invalid;
    info["samples_lost"] = s.counters.samples_lost;
    info["frames_not_published"] = s.frames_not_published;  // estimated while another serve published them
    info["latency_ms"] = LatencyJson(s.latency);
    try {
      WriteKittiTrajectory(dir + "/camera_ours.kitti", ReadTumTrajectory(dir + "/camera_ours.tum"));
      nlohmann::json metrics;
      // No ground truth on a vehicle: no error metrics, only the back-end's time.
      metrics["methods"]["ours"] = {{"wall_time_s", result_->wall_time_s}};
      metrics["run"] = info;
      WholeFile out(dir + "/metrics.json");
      out << metrics.dump(2) << '\n';
      out.commit();
    } catch (const std::exception& e) {
      log << "vehicle '" << name_ << "': " << e.what() << std::endl;
      return;
    }
    log << "vehicle '" << name_ << "': " << frames << " frames, results written to " << dir << std::endl;
  }

 private:
  static std::string ResultDir(const ServeOptions& options, const std::string& name) {
    return options.out_dir + "/" + (name.empty() ? "default" : name);
  }

  // Up to this many samples (colour, depth, mask, odometry and some slack) per waiting frame in the inbox.
  static constexpr size_t kInboxSamplesPerFrame = 6;

  struct Sample {
    int64_t arrived_ns = 0;         // taken from the reader (steady clock)
    std::optional<ImageRole> role;  // none: odometry or a LiDAR scan
    bool is_compressed = false;     // the image is in `compressed`, not `image`
    bool is_lidar = false;
    sensor_msgs::msg::Image image;
    sensor_msgs::msg::CompressedImage compressed;
    nav_msgs::msg::Odometry odometry;
    sensor_msgs::msg::PointCloud2 cloud;
  };

  // One input topic: each sample taken from its reader goes into the inbox with its arrival time, as a
  // copy of `prototype` (which says what the sample is) with the message in its `message` field.
  template <class Msg>
  class InputListener : public dds::DataReaderListener {
   public:
    InputListener(Vehicle* v, Sample prototype, Msg Sample::*message)
        : vehicle_(v), prototype_(std::move(prototype)), message_(message) {}
    void on_data_available(dds::DataReader* reader) override {
      Sample sample = prototype_;
      dds::SampleInfo info;
      while (reader->take_next_sample(&(sample.*message_), &info) == ReturnCode_t::RETCODE_OK) {
        sample.arrived_ns = SteadyClockNs();
        if (info.valid_data) vehicle_->inbox_.pushDropOldest(sample);
      }
    }
    void on_sample_lost(dds::DataReader*, const dds::SampleLostStatus& status) override {
      vehicle_->samples_lost_ += static_cast<uint64_t>(std::max(0, status.total_count_change));
    }

   private:
    Vehicle* vehicle_;
    Sample prototype_;
    Msg Sample::*message_;
  };
  static Sample ImageSample(ImageRole role, bool compressed = false) {
    Sample s;
    s.role = role;
    s.is_compressed = compressed;
    return s;
  }
  static Sample LidarSample() {
    Sample s;
    s.is_lidar = true;
    return s;
  }

  // The intake thread: decodes samples (off Fast DDS' receive thread) and assembles frames.
  void runIntake() {
    while (std::optional<Sample> sample = inbox_.pop()) {
      if (abandon_) continue;  // asked twice to stop: the backlog is dropped
      if (sample->role) {
        const ImageRole role = *sample->role;
        const int64_t decode_start_ns = SteadyClockNs();
        DecodedImage decoded = sample->is_compressed ? DecodeCompressedImage(sample->compressed, role)
                                                     : DecodeImage(sample->image, role);
        const PartArrival arrival{sample->arrived_ns, 1e-6 * static_cast<double>(SteadyClockNs() - decode_start_ns)};
        const int64_t t_ns = StampToNs(sample->is_compressed ? sample->compressed.header().stamp()
                                                             : sample->image.header().stamp());
        std::lock_guard<std::mutex> lock(mutex_);
        if (!decoded.error.empty()) {
          assembler_.reject(decoded.error);
        } else if (role == ImageRole::kColour) {
          assembler_.addColour(t_ns, decoded.image, arrival);
        } else if (role == ImageRole::kDepth) {
          assembler_.addDepth(t_ns, decoded.image, arrival);
        } else {
          assembler_.addMask(t_ns, decoded.image, arrival);
        }
      } else if (sample->is_lidar) {
        const int64_t decode_start_ns = SteadyClockNs();
        DecodedPointCloud decoded = DecodePointCloud(sample->cloud);
        LidarPart scan;
        if (decoded.error.empty()) {
          ImageFrame in_camera;  // the same transform as a dataset reader's (SetLidarScan)
          SetLidarScan(decoded.points, *options_.T_camera_lidar, &in_camera);
          scan = {std::move(in_camera.lidar_points_camera), in_camera.lidar_origin_camera, in_camera.lidar_up_camera};
        }
        const PartArrival arrival{sample->arrived_ns, 1e-6 * static_cast<double>(SteadyClockNs() - decode_start_ns)};
        std::lock_guard<std::mutex> lock(mutex_);
        if (decoded.error.empty())
          assembler_.addLidar(StampToNs(sample->cloud.header().stamp()), std::move(scan), arrival);
        else
          assembler_.reject(decoded.error);
      } else {
        std::string error;
        const auto pose = DecodeOdometry(sample->odometry, &error);
        std::lock_guard<std::mutex> lock(mutex_);
        if (pose) {
          assembler_.addOdometry(StampToNs(sample->odometry.header().stamp()), *pose, {sample->arrived_ns, 0.0});
        } else {
          assembler_.reject(error);
        }
      }
      wake_.notify_one();
    }
  }

  // The feeder thread: assembled frames into the pipeline. When the pipeline is busy, push() waits and
  // the assembler keeps collecting: it drops its oldest waiting sets (counted) beyond --max-pending.
  void runFeeder() {
    for (;;) {
      std::vector<ImageFrame> frames;
      bool counters_changed = false;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait_for(lock, std::chrono::milliseconds(50));
        frames = assembler_.takeReady();
        const auto now = Clock::now();
        for (const ImageFrame& f : frames) handed_at_[f.t_ns] = now;
        counters_changed = ProblemCount(countersLocked()) != published_problems_;
        if (frames.empty() && stopping_) return;
      }
      if (abandon_) return;
      for (ImageFrame& frame : frames) {
        makeMasks(frame);
        if (options_.every_frame)
          pipeline_->push(std::move(frame));
        else
          pipeline_->pushNewest(std::move(frame));
      }
      // Drops and rejections with no frame to follow (a stream that stopped, a stream of bad samples)
      // are reported too, stamped with the wall time.
      if (frames.empty() && counters_changed) publishStatus(SystemClockNs());
    }
  }

  // Masks from the frame's LiDAR scan (masks.source: lidar_clusters), on the feeder's thread: its time
  // counts in the frame's input stage. When they cannot be made (an empty scan) the problem is counted
  // as a rejection and the frame goes on without masks (all static), so that its odometry is not lost.
  void makeMasks(ImageFrame& frame) {
    if (masks_.source == MaskSourceKind::kDataset) return;
    try {
      PinholeCamera camera = options_.camera;
      camera.width = frame.image.cols, camera.height = frame.image.rows;
      ApplyMaskSource(masks_, camera, frame);
    } catch (const std::exception& e) {
      frame.instance_ids.release();
      std::lock_guard<std::mutex> lock(mutex_);
      assembler_.reject(std::string("frame at ") + std::to_string(frame.t_ns) + " ns: no masks: " + e.what());
    }
    frame.timing.assembled_ns = SteadyClockNs();
  }

  // The assembler's counters plus the samples the inbox dropped (as queue-full drops). Under mutex_.
  AssemblerCounters countersLocked() const {
    AssemblerCounters c = assembler_.counters();
    c.dropped_queue_full += inbox_.dropped() + pipeline_->framesDropped();
    c.samples_lost = samples_lost_;
    return c;
  }

  // Drops, rejections and lost samples so far; the counters only grow, so their sum changes whenever one does.
  static uint64_t ProblemCount(const AssemblerCounters& c) {
    return c.dropped_queue_full + c.dropped_incomplete + c.rejected_invalid + c.samples_lost + c.frames_missing;
  }

  static int64_t SystemClockNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
        .count();
  }

  // The back-end thread, after each frame.
  void publish(const FrameEstimate& estimate, const FrameTiming& timing_in) {
    ++frames_processed_;  // only this thread writes it until writeResults, after finish()
    const bool quiet = quiet_;
    if (!quiet) {
      nav_msgs::msg::Odometry odometry = EncodeOdometry(estimate.T_world_camera, estimate.t_ns, "world", "camera");
      odometry_writer_->write(&odometry);
      dslam_msgs::msg::ObjectMotionArray objects = ToMessage(estimate, options_.frame_rate_hz);
      objects_writer_->write(&objects);
      visualization_msgs::msg::MarkerArray markers = ObjectMarkers(estimate, options_.frame_rate_hz);
      markers_writer_->write(&markers);
    }
    FrameTiming timing = timing_in;
    timing.published_ns = SteadyClockNs();
    // Capture to estimate is known when the stamps are of this host's clock (a driver here, or one
    // synchronised with it): a stamp from another epoch (a replay's, a sensor's own) is not compared.
    const double since_capture_ms = 1e-6 * static_cast<double>(SystemClockNs() - estimate.t_ns);
    latency_.add(timing, since_capture_ms >= 0.0 && since_capture_ms < 60'000.0 ? since_capture_ms : -1.0);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++status_.frames_processed;
      status_.frames_not_published += quiet;
      const auto it = handed_at_.find(estimate.t_ns);
      if (it != handed_at_.end()) {
        status_.last_latency_ms = std::chrono::duration<double, std::milli>(Clock::now() - it->second).count();
        handed_at_.erase(handed_at_.begin(), std::next(it));
      }
    }
    publishStatus(estimate.t_ns);
  }

  void publishStatus(int64_t t_ns) {
    if (quiet_) return;  // the status is one of the estimates' outputs: the publishing serve's alone
    dslam_msgs::msg::Status status;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const AssemblerCounters c = countersLocked();
      status.header().stamp(NsToStamp(t_ns));
      status.vehicle(name_);
      status.frames_received(c.parts_received);
      status.frames_assembled(c.frames_assembled);
      status.frames_processed(status_.frames_processed);
      status.dropped_incomplete(c.dropped_incomplete);
      status.dropped_queue_full(c.dropped_queue_full);
      status.rejected_invalid(c.rejected_invalid);
      status.samples_lost(c.samples_lost);
      status.last_rejection(c.last_rejection);
      status.last_latency_ms(status_.last_latency_ms);
      published_problems_ = ProblemCount(c);
    }
    // The back-end and the feeder both publish statuses.
    std::lock_guard<std::mutex> lock(status_writer_mutex_);
    status_writer_->write(&status);
  }

  std::string name_;
  ServeOptions options_;
  MaskSourceParams masks_;
  mutable std::mutex mutex_;  // assembler, status, handed_at_
  std::condition_variable wake_;
  bool stopping_ = false;
  FrameAssembler assembler_;
  VehicleStatus status_;
  std::map<int64_t, Clock::time_point> handed_at_;  // stamps handed to the pipeline -> when (for the latency)
  StageLatency latency_;  // per stage, over the session
  // Drops and rejections as of the last status message, to publish a new one when one more happens.
  uint64_t published_problems_ = 0;
  BoundedQueue<Sample> inbox_;
  std::atomic<uint64_t> samples_lost_{0};  // by Fast DDS' threads (SAMPLE_LOST of the input readers)
  DirLock dir_lock_;          // this vehicle's folder is ours alone while we run
  std::atomic<bool> abandon_{false};
  std::atomic<bool> quiet_{false};  // estimates, results on disk, nothing published (setQuiet)
  StreamingFileSink stream_;  // the results as they become final; rewritten whole at the end
  std::unique_ptr<StagedPipeline> pipeline_;
  std::optional<MethodResult> result_;  // once stopped
  std::string pipeline_failure_;
  uint64_t frames_processed_ = 0;
  std::mutex status_writer_mutex_;
  InputListener<sensor_msgs::msg::Image> colour_listener_, depth_listener_, mask_listener_;
  InputListener<sensor_msgs::msg::CompressedImage> colour_compressed_listener_, depth_compressed_listener_,
      mask_compressed_listener_;
  InputListener<sensor_msgs::msg::PointCloud2> lidar_listener_;
  InputListener<nav_msgs::msg::Odometry> odometry_listener_;
  dds::DataWriter *odometry_writer_ = nullptr, *objects_writer_ = nullptr, *status_writer_ = nullptr,
                  *markers_writer_ = nullptr;
  dds::DataWriterQos estimate_qos_;
  RosGraphNode graph_node_;
  std::thread intake_, feeder_;
};

// Watches the network for another serve publishing one of our vehicles' estimates where subscribers would
// take both streams, and makes the instance whose participant GUID is the higher go quiet for that vehicle
// (fleet_share.h, YieldsTo) until the other's writer is gone. Hot standbys (exclusive ownership, different
// strengths) are left alone: DDS already gives subscribers one of them.
class RivalWriterWatch : public dds::DomainParticipantListener {
 public:
  explicit RivalWriterWatch(const std::vector<std::string>& vehicles) {
    for (const std::string& name : vehicles) vehicle_of_topic_[TopicsFor(name).camera_odometry] = name;
  }

  // Our estimates' ownership, known once the session has read the profiles; the vehicles exist after the
  // participant. Each vehicle is told its state as it attaches, and on every change after.
  void setOwnership(const dds::DataWriterQos& qos) {
    std::lock_guard<std::mutex> lock(mutex_);
    exclusive_ = qos.ownership().kind == dds::EXCLUSIVE_OWNERSHIP_QOS;
    strength_ = qos.ownership_strength().value;
    for (const auto& [name, vehicle] : vehicles_) vehicle->setQuiet(yieldingTo(name));
  }
  void attach(const std::string& name, Vehicle* vehicle) {
    std::lock_guard<std::mutex> lock(mutex_);
    vehicles_[name] = vehicle;
    vehicle->setQuiet(yieldingTo(name));
  }

  void on_publisher_discovery(dds::DomainParticipant* participant,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override {
    const auto topic = vehicle_of_topic_.find(info.info.topicName().to_string());
    if (topic == vehicle_of_topic_.end()) return;
    Prefix own, other;
    std::copy(std::begin(participant->guid().guidPrefix.value), std::end(participant->guid().guidPrefix.value), own.begin());
    std::copy(std::begin(info.info.guid().guidPrefix.value), std::end(info.info.guid().guidPrefix.value), other.begin());
    if (own == other) return;  // our own writer
    std::lock_guard<std::mutex> lock(mutex_);
    own_ = own;
    auto& writers = remote_writers_[topic->second];
    if (info.status == eprosima::fastrtps::rtps::WriterDiscoveryInfo::REMOVED_WRITER)
      writers.erase(other);
    else
      writers[other] = {info.info.m_qos.m_ownership.kind == dds::EXCLUSIVE_OWNERSHIP_QOS,
                        info.info.m_qos.m_ownershipStrength.value};
    const auto v = vehicles_.find(topic->second);
    if (v != vehicles_.end()) v->second->setQuiet(yieldingTo(topic->second));
  }

 private:
  using Prefix = std::array<uint8_t, 12>;
  struct Ownership {
    bool exclusive = false;
    uint32_t strength = 0;
  };

  // The lowest remote participant this instance yields to for the vehicle, in hex; "" when none.
  std::string yieldingTo(const std::string& name) const {
    const auto it = remote_writers_.find(name);
    if (it == remote_writers_.end()) return {};
    for (const auto& [prefix, ownership] : it->second) {  // ascending
      const bool both_reach_subscribers = !exclusive_ || !ownership.exclusive || ownership.strength == strength_;
      if (!both_reach_subscribers || !YieldsTo(own_, prefix)) continue;
      std::string hex;
      for (uint8_t byte : prefix) {
        static const char* digits = "0123456789abcdef";
        hex += digits[byte >> 4], hex += digits[byte & 15];
      }
      return hex;
    }
    return {};
  }

  std::map<std::string, std::string> vehicle_of_topic_;  // camera odometry topic -> vehicle
  std::mutex mutex_;
  bool exclusive_ = false;
  uint32_t strength_ = 0;
  Prefix own_{};
  std::map<std::string, std::map<Prefix, Ownership>> remote_writers_;  // vehicle -> other serves' writers
  std::map<std::string, Vehicle*> vehicles_;
};

struct ServeNode::Impl {
  // Also when the constructor throws half-way: the vehicles finish while the writers exist, and the readers
  // go with the session before the vehicles their listeners point to.
  ~Impl() {
    for (auto& [name, v] : vehicles) v->stop();
    graph.reset();
    session.reset();
  }
  std::unique_ptr<RivalWriterWatch> watch;  // outlives the session, whose participant calls it
  std::unique_ptr<DdsSession> session;
  std::map<std::string, std::unique_ptr<Vehicle>> vehicles;
  std::unique_ptr<RosGraphAnnouncer> graph;
};

ServeNode::ServeNode(const ServeOptions& options_in, const RunConfig& config) : impl_(std::make_unique<Impl>()) {
  config.validate();
  ServeOptions options = options_in;
  // The assembler counts frames lost whole against the sensor's period (a bad rate is the pipeline's error).
  if (std::isfinite(options.frame_rate_hz) && options.frame_rate_hz > 0.0)
    options.assembler.nominal_period_ns = std::llround(1e9 / options.frame_rate_hz);
  if (config.masks.source == MaskSourceKind::kLidarClusters) {
    // Masks made from each frame's LiDAR scan: a frame needs a scan, not a mask.
    if (!options.T_camera_lidar)
      throw std::invalid_argument("masks.source lidar_clusters needs the LiDAR's pose in the camera (Tr_velo_to_cam "
                                  "in the calibration)");
    options.assembler.expect_mask = false;
    options.assembler.expect_lidar = true;
  }
  for (const std::string& name : options.vehicles)
    if (const std::string bad = FindInvalidVehicleName(name); !bad.empty()) throw std::invalid_argument(bad);
  if (const std::string bad = FindInvalidNodeName(options.node_name); !bad.empty()) throw std::invalid_argument(bad);
  RosGidWidth(options.ros_distro);  // throws for an unknown distribution, before DDS starts
  impl_->watch = std::make_unique<RivalWriterWatch>(options.vehicles);
  impl_->session = std::make_unique<DdsSession>(options.domain_id, options.profiles_file, impl_->watch.get());
  for (const std::string& name : options.vehicles) {
    if (impl_->vehicles.count(name)) throw std::invalid_argument("vehicle '" + name + "' given twice");
    impl_->vehicles[name] = std::make_unique<Vehicle>(*impl_->session, name, options, config);
  }
  if (!impl_->vehicles.empty()) impl_->watch->setOwnership(impl_->vehicles.begin()->second->estimateQos());
  for (const auto& [name, v] : impl_->vehicles) impl_->watch->attach(name, v.get());
  impl_->graph = std::make_unique<RosGraphAnnouncer>(*impl_->session, options.ros_distro);
  std::vector<RosGraphNode> nodes;
  for (const auto& [name, v] : impl_->vehicles) nodes.push_back(v->graphNode());
  impl_->graph->announce(nodes);
}

ServeNode::~ServeNode() = default;

std::map<std::string, VehicleStatus> ServeNode::status() const {
  std::map<std::string, VehicleStatus> out;
  for (const auto& [name, v] : impl_->vehicles) {
    out[name] = v->status();
    if (impl_->session) out[name].estimate_readers = v->estimateReaders();  // not after shutdown(): no writers
  }
  return out;
}

void ServeNode::abandonBacklogs() {
  for (auto& [name, v] : impl_->vehicles) v->abandonBacklog();
}

void ServeNode::shutdown(std::ostream& log) {
  for (auto& [name, v] : impl_->vehicles) v->stop();
  // Every estimate published reaches the subscribers before the participant goes: on a lossy link the last
  // ones may still need a repair (at most 2 s each writer; a subscriber that is gone does not hold it up).
  for (auto& [name, v] : impl_->vehicles) v->waitForAcknowledgments();
  impl_->graph.reset();
  impl_->session.reset();  // no more samples
  for (auto& [name, v] : impl_->vehicles) v->writeResults(log);
}

}  // namespace dslam
