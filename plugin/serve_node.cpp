#include "plugin/serve_node.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <thread>

#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "dslam_msgsPubSubTypes.h"
#include "nav_msgs_OdometryPubSubTypes.h"
#include "output/run_report.h"
#include "output/trajectory_io.h"
#include "plugin/dds_session.h"
#include "plugin/image_message.h"
#include "plugin/topics.h"
#include "plugin/vehicle_pipeline.h"
#include "sensor_msgs_ImagePubSubTypes.h"

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
    const Vec3 v = m.velocity_world_per_frame * frame_rate_hz;
    o.velocity_mps().x(v.x()), o.velocity_mps().y(v.y()), o.velocity_mps().z(v.z());
    o.speed_mps(m.speed_mps);
    const Vec3 centroid_world = m.H_world * m.centroid_prev_world;  // the points moved rigidly by H into k
    o.centroid_world().x(centroid_world.x()), o.centroid_world().y(centroid_world.y());
    o.centroid_world().z(centroid_world.z());
    o.is_dynamic(m.is_dynamic);
    msg.objects().push_back(o);
  }
  return msg;
}

}  // namespace

// One vehicle: its readers feed the assembler; a worker thread runs the pipeline and publishes.
class Vehicle {
 public:
  Vehicle(DdsSession& session, const std::string& name, const ServeOptions& options, const RunConfig& config)
      : name_(name),
        options_(options),
        assembler_(options.assembler),
        pipeline_(config, options.camera, options.frame_rate_hz),
        colour_listener_(this, ImageRole::kColour),
        depth_listener_(this, ImageRole::kDepth),
        mask_listener_(this, ImageRole::kMask),
        odometry_listener_(this) {
    const VehicleTopics topics = TopicsFor(name);
    odometry_writer_ = session.writer(topics.camera_odometry, new nav_msgs::msg::OdometryPubSubType(), "estimate_writer");
    objects_writer_ =
        session.writer(topics.object_motions, new dslam_msgs::msg::ObjectMotionArrayPubSubType(), "estimate_writer");
    status_writer_ = session.writer(topics.status, new dslam_msgs::msg::StatusPubSubType(), "estimate_writer");
    worker_ = std::thread([this] { run(); });
    session.reader(topics.colour, new sensor_msgs::msg::ImagePubSubType(), "sensor_reader", &colour_listener_);
    session.reader(topics.depth, new sensor_msgs::msg::ImagePubSubType(), "sensor_reader", &depth_listener_);
    session.reader(topics.mask, new sensor_msgs::msg::ImagePubSubType(), "sensor_reader", &mask_listener_);
    session.reader(topics.odometry, new nav_msgs::msg::OdometryPubSubType(), "sensor_reader", &odometry_listener_);
  }

  ~Vehicle() { stop(); }

  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (worker_.joinable()) worker_.join();
  }

  VehicleStatus status() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return status_;
  }

  void writeResults(std::ostream& log) {
    std::lock_guard<std::mutex> lock(pipeline_mutex_);
    const std::string dir = options_.out_dir + "/" + (name_.empty() ? "default" : name_);
    if (pipeline_.framesProcessed() == 0) {
      log << "vehicle '" << name_ << "': no frame processed, nothing written" << std::endl;
      return;
    }
    MethodOutcomes outcomes;
    outcomes[Method::kOurs].result.estimate = pipeline_.finish();
    outcomes[Method::kOurs].result.online = online_;
    nlohmann::json info;
    info["command"] = "serve";
    info["vehicle"] = name_;
    info["frames"] = pipeline_.framesProcessed();
    const VehicleStatus s = status();
    info["frames_received"] = s.counters.parts_received;
    info["frames_assembled"] = s.counters.frames_assembled;
    info["dropped_incomplete"] = s.counters.dropped_incomplete;
    info["dropped_queue_full"] = s.counters.dropped_queue_full;
    info["rejected_invalid"] = s.counters.rejected_invalid;
    WriteRunOutputs(dir, pipeline_.sequence(), outcomes, info);
    log << "vehicle '" << name_ << "': " << pipeline_.framesProcessed() << " frames, results written to " << dir
        << std::endl;
  }

  void onImage(ImageRole role, const sensor_msgs::msg::Image& msg) {
    DecodedImage decoded = DecodeImage(msg, role);
    const int64_t t_ns = StampToNs(msg.header().stamp());
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!decoded.error.empty()) {
        assembler_.reject(decoded.error);
      } else if (role == ImageRole::kColour) {
        assembler_.addColour(t_ns, decoded.image);
      } else if (role == ImageRole::kDepth) {
        assembler_.addDepth(t_ns, decoded.image);
      } else {
        assembler_.addMask(t_ns, decoded.image);
      }
    }
    wake_.notify_one();
  }

  void onOdometry(const nav_msgs::msg::Odometry& msg) {
    std::string error;
    const auto pose = DecodeOdometry(msg, Vec6::Constant(0.01), &error);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (pose) {
        assembler_.addOdometry(StampToNs(msg.header().stamp()), *pose);
      } else {
        assembler_.reject(error);
      }
    }
    wake_.notify_one();
  }

 private:
  class ImageListener : public dds::DataReaderListener {
   public:
    ImageListener(Vehicle* v, ImageRole role) : vehicle_(v), role_(role) {}
    void on_data_available(dds::DataReader* reader) override {
      sensor_msgs::msg::Image msg;
      dds::SampleInfo info;
      while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK)
        if (info.valid_data) vehicle_->onImage(role_, msg);
    }

   private:
    Vehicle* vehicle_;
    ImageRole role_;
  };
  class OdometryListener : public dds::DataReaderListener {
   public:
    explicit OdometryListener(Vehicle* v) : vehicle_(v) {}
    void on_data_available(dds::DataReader* reader) override {
      nav_msgs::msg::Odometry msg;
      dds::SampleInfo info;
      while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK)
        if (info.valid_data) vehicle_->onOdometry(msg);
    }

   private:
    Vehicle* vehicle_;
  };

  void run() {
    for (;;) {
      std::vector<ImageFrame> frames;
      bool counters_changed = false;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait_for(lock, std::chrono::milliseconds(50));
        frames = assembler_.takeReady();
        status_.counters = assembler_.counters();
        counters_changed = ProblemCount(status_.counters) != published_problems_;
        if (frames.empty() && stopping_) return;
      }
      for (const ImageFrame& frame : frames) process(frame);
      // Drops and rejections with no frame to follow (a stream that stopped, a stream of bad samples)
      // are reported too, stamped with the wall time.
      if (frames.empty() && counters_changed) publishStatus(SystemClockNs());
    }
  }

  // Drops and rejections so far; the counters only grow, so their sum changes whenever one of them does.
  static uint64_t ProblemCount(const AssemblerCounters& c) {
    return c.dropped_queue_full + c.dropped_incomplete + c.rejected_invalid;
  }

  static int64_t SystemClockNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
        .count();
  }

  void process(const ImageFrame& frame) {
    const auto start = Clock::now();
    FrameEstimate estimate;
    {
      std::lock_guard<std::mutex> lock(pipeline_mutex_);
      try {
        estimate = pipeline_.process(frame);
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> status_lock(mutex_);
        assembler_.reject(std::string("frame at ") + std::to_string(frame.t_ns) + " ns: " + e.what());
        return;
      }
      online_.push_back(estimate);
    }
    nav_msgs::msg::Odometry odometry = EncodeOdometry(estimate.T_world_camera, frame.t_ns, "world", "camera");
    odometry_writer_->write(&odometry);
    dslam_msgs::msg::ObjectMotionArray objects = ToMessage(estimate, options_.frame_rate_hz);
    objects_writer_->write(&objects);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++status_.frames_processed;
      status_.last_latency_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    }
    publishStatus(frame.t_ns);
  }

  void publishStatus(int64_t t_ns) {
    dslam_msgs::msg::Status status;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const AssemblerCounters& c = assembler_.counters();
      status.header().stamp(NsToStamp(t_ns));
      status.vehicle(name_);
      status.frames_received(c.parts_received);
      status.frames_assembled(c.frames_assembled);
      status.frames_processed(status_.frames_processed);
      status.dropped_incomplete(c.dropped_incomplete);
      status.dropped_queue_full(c.dropped_queue_full);
      status.rejected_invalid(c.rejected_invalid);
      status.last_rejection(c.last_rejection);
      status.last_latency_ms(status_.last_latency_ms);
      published_problems_ = ProblemCount(c);
    }
    status_writer_->write(&status);
  }

  std::string name_;
  ServeOptions options_;
  mutable std::mutex mutex_;  // assembler and status
  std::condition_variable wake_;
  bool stopping_ = false;
  FrameAssembler assembler_;
  VehicleStatus status_;
  // Drops and rejections as of the last status message, to publish a new one when one more happens.
  uint64_t published_problems_ = 0;
  std::mutex pipeline_mutex_;
  VehiclePipeline pipeline_;
  std::vector<FrameEstimate> online_;
  ImageListener colour_listener_, depth_listener_, mask_listener_;
  OdometryListener odometry_listener_;
  dds::DataWriter *odometry_writer_ = nullptr, *objects_writer_ = nullptr, *status_writer_ = nullptr;
  std::thread worker_;
};

struct ServeNode::Impl {
  std::unique_ptr<DdsSession> session;
  std::map<std::string, std::unique_ptr<Vehicle>> vehicles;
};

ServeNode::ServeNode(const ServeOptions& options, const RunConfig& config) : impl_(std::make_unique<Impl>()) {
  config.validate();
  impl_->session = std::make_unique<DdsSession>(options.domain_id, options.profiles_file);
  for (const std::string& name : options.vehicles) {
    if (impl_->vehicles.count(name)) throw std::invalid_argument("vehicle '" + name + "' given twice");
    impl_->vehicles[name] = std::make_unique<Vehicle>(*impl_->session, name, options, config);
  }
}

ServeNode::~ServeNode() {
  // Readers go with the session before the vehicles their listeners point to.
  for (auto& [name, v] : impl_->vehicles) v->stop();
  impl_->session.reset();
}

std::map<std::string, VehicleStatus> ServeNode::status() const {
  std::map<std::string, VehicleStatus> out;
  for (const auto& [name, v] : impl_->vehicles) out[name] = v->status();
  return out;
}

void ServeNode::shutdown(std::ostream& log) {
  for (auto& [name, v] : impl_->vehicles) v->stop();
  impl_->session.reset();  // no more samples
  for (auto& [name, v] : impl_->vehicles) v->writeResults(log);
}

}  // namespace dslam
