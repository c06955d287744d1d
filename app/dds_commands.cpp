#include "app/dds_commands.h"

#include <atomic>
#include <cmath>
#include <chrono>
#include <map>
#include <mutex>
#include <iomanip>
#include <csignal>
#include <filesystem>
#include <thread>

#include "data/kitti_tracking.h"
#include "output/whole_file.h"
#include "output/whole_line_file.h"
#include "pipeline/config_yaml.h"
#include "plugin/dds_error.h"
#include "plugin/estimate_listener.h"
#include "plugin/estimate_stream_stats.h"
#include "plugin/fleet_share.h"
#include "plugin/ros_distro.h"
#include "plugin/topics.h"
#include "plugin/udp_buffer_check.h"

namespace dslam {
namespace {

std::atomic<bool> g_stop{false};
std::atomic<int> g_stop_signals{0};  // lock-free: safe to touch in a signal handler
extern "C" void OnStopSignal(int) {
  g_stop = true;
  ++g_stop_signals;
}

void InstallStopHandlers() {
  g_stop = false;
  g_stop_signals = 0;
  std::signal(SIGINT, OnStopSignal);
  std::signal(SIGTERM, OnStopSignal);
}

}  // namespace

RunConfig ServeRunConfig(const ServeCommandOptions& options) {
  const RunConfig base = DefaultRunConfig(EntryPoint::kServe);  // under the configuration file
  RunConfig config = options.config_path ? LoadRunConfig(*options.config_path, base) : base;
  // Estimates leave serve frame by frame; a batch solve has none until the stream ends.
  if (config.backend.schedule.kind == ScheduleKind::kBatch)
    throw std::invalid_argument(*options.config_path + ": backend.schedule batch is an offline schedule (dslam run "
                                "--schedule batch); serve estimates online: use window:W");
  return config;
}

int RunServeCommand(const ServeCommandOptions& options, std::ostream& out, std::ostream& err) {
  ServeOptions serve;
  RunConfig config;
  try {
    config = ServeRunConfig(options);
    if (options.calib_path.empty()) throw std::invalid_argument("--calib FILE is required (KITTI calib.txt format)");
    // The same ranges as the command line's, for callers that build the options themselves.
    if (!std::isfinite(options.frame_rate_hz) || options.frame_rate_hz < 1e-3 || options.frame_rate_hz > 1000.0)
      throw std::invalid_argument("--rate must be between 0.001 and 1000 Hz, got " + std::to_string(options.frame_rate_hz));
    if (!std::isfinite(options.status_every_s) || options.status_every_s < 0.0 || options.status_every_s > 86400.0)
      throw std::invalid_argument("--status-every must be between 0 and 86400 s, got " + std::to_string(options.status_every_s));
    if (!std::isfinite(options.max_run_s) || options.max_run_s < 0.0 || options.max_run_s > 1e9)
      throw std::invalid_argument("--max-run must be between 0 and 1e9 s, got " + std::to_string(options.max_run_s));
    if (std::error_code ec; std::filesystem::exists(options.out_dir, ec) && !std::filesystem::is_directory(options.out_dir, ec))
      throw std::invalid_argument("--out " + options.out_dir + " is a file, not a folder to write results into");
    std::vector<std::string> fleet_share;  // this host's vehicles of the fleet
    if (!options.fleet_share.empty()) {
      if (options.vehicles.empty()) throw std::invalid_argument("--fleet-share needs the fleet's --vehicle list");
      fleet_share = VehiclesOfShare(options.vehicles, ParseFleetShare(options.fleet_share));
      if (fleet_share.empty())
        throw std::invalid_argument("--fleet-share " + options.fleet_share + " leaves this host no vehicle of the " +
                                    std::to_string(options.vehicles.size()) + " given");
    }
    const KittiCalibration calib = ReadKittiCalibration(options.calib_path);
    const auto& P = calib.P[2](0, 0) > 0.0 ? calib.P[2] : calib.P[0];
    serve.camera.fx = P(0, 0), serve.camera.fy = P(1, 1), serve.camera.cx = P(0, 2), serve.camera.cy = P(1, 2);
    serve.camera.width = serve.camera.height = 0;  // from the first frame
    // Masks from the LiDAR topic's scans (in the LiDAR's frame): the calibration must place the LiDAR.
    if (config.masks.source == MaskSourceKind::kLidarClusters) {
      if (!calib.has_T_cam_velo)
        throw std::invalid_argument(options.calib_path + ": masks.source lidar_clusters needs Tr_velo_to_cam (the "
                                    "LiDAR's pose in the camera) in the calibration");
      serve.T_camera_lidar = calib.T_camera_lidar();
    }
    serve.domain_id = options.domain_id;
    serve.profiles_file = options.profiles_file;
    if (!options.vehicles.empty()) serve.vehicles = options.vehicles;
    if (!options.fleet_share.empty()) serve.vehicles = fleet_share;
    serve.assembler.expect_odometry = !options.no_odometry;
    serve.assembler.timeout_ns = static_cast<int64_t>(options.timeout_ms) * 1'000'000;
    serve.assembler.silence_timeout_ns = static_cast<int64_t>(options.silence_ms) * 1'000'000;
    serve.assembler.max_pending = options.max_pending;
    serve.every_frame = options.every_frame;
    if (options.max_pending_mb < 16 || options.max_pending_mb > 8192)
      throw std::invalid_argument("--max-pending-mb must be in 16..8192");
    serve.assembler.max_pending_bytes = static_cast<size_t>(options.max_pending_mb) << 20;
    serve.frame_rate_hz = options.frame_rate_hz;
    serve.out_dir = options.out_dir;
    if (options.domain_id < 0 || options.domain_id > 232) throw std::invalid_argument("--domain must be in 0..232");
    for (const std::string& name : serve.vehicles)
      if (const std::string bad = FindInvalidVehicleName(name); !bad.empty()) throw std::invalid_argument(bad);
    if (const std::string bad = FindInvalidNodeName(options.node_name); !bad.empty())
      throw std::invalid_argument("--node-name: " + bad);
    serve.node_name = options.node_name;
    RosGidWidth(options.ros_distro);  // throws for an unknown one
    serve.ros_distro = options.ros_distro;
    if (options.ownership_strength >= 0) serve.ownership_strength = static_cast<uint32_t>(options.ownership_strength);
    serve.assembler.validate();
  } catch (const std::exception& e) {
    err << "dslam serve: error: " << e.what() << std::endl;
    return 2;
  }
  InstallStopHandlers();
  try {
    ServeNode node(serve, config);
    out << "dslam serve: domain " << options.domain_id << ", vehicles:";
    for (const auto& v : serve.vehicles) out << " '" << v << "'";
    out << "; waiting for frames (SIGINT or SIGTERM to stop)" << std::endl;
    if (const auto requested = ProfileUdpReceiveBuffer(serve.profiles_file)) {
      if (const auto warning = CheckUdpReceiveBuffer(*requested)) err << "dslam serve: warning: " << *warning << std::endl;
    } else {
      err << "dslam serve: warning: " << serve.profiles_file
          << " gives the UDPv4 transport no receiveBufferSize: images over UDP will lose fragments (docs/serve.md, "
             "QoS and the vehicle network)"
          << std::endl;
    }
    const auto start = std::chrono::steady_clock::now();
    auto last_status = start, last_loss_warning = start - std::chrono::hours(1);
    std::map<std::string, uint64_t> lost_reported;
    std::map<std::string, std::string> quiet_reported;  // vehicle -> the serve it yields to ("" = publishing)
    std::map<std::string, int> readers_reported;        // vehicle -> subscribers matched, as last said
    while (!g_stop) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      const auto now = std::chrono::steady_clock::now();
      const std::map<std::string, VehicleStatus> statuses = node.status();  // one snapshot for the lines below
      // Another serve publishing one of our vehicles: said at once, and again when it leaves.
      for (const auto& [name, s] : statuses) {
        if (s.quiet_for == quiet_reported[name]) continue;
        if (s.quiet)
          out << "dslam serve: warning: vehicle '" << name << "' is also published by another serve (participant "
              << s.quiet_for << ") that subscribers would take as well: this one goes quiet (it estimates and writes "
                 "its results, publishes nothing) while that one publishes; see docs/serve.md, A fleet"
              << std::endl;
        else
          out << "dslam serve: vehicle '" << name << "': the other serve is gone, this one publishes again" << std::endl;
        quiet_reported[name] = s.quiet_for;
      }
      // Subscribers matched, said as it changes: discovery is not symmetric, and a subscriber gets only the
      // estimates written once serve's writer has matched it (a script can wait for this line).
      for (const auto& [name, s] : statuses) {
        if (s.estimate_readers == readers_reported[name]) continue;
        readers_reported[name] = s.estimate_readers;
        out << "dslam serve: vehicle '" << name << "': " << s.estimate_readers
            << (s.estimate_readers == 1 ? " reader" : " readers") << " of camera estimates matched" << std::endl;
      }
      // Lost input samples are a network problem the user can fix: said at once, at most every 5 s.
      if (now - last_loss_warning > std::chrono::seconds(5)) {
        for (const auto& [name, s] : statuses) {
          if (s.counters.samples_lost <= lost_reported[name]) continue;
          out << "dslam serve: warning: vehicle '" << name << "': " << s.counters.samples_lost
              << " input samples lost so far (gaps in the writers' sequence numbers: over UDP usually fragments the "
                 "socket buffer could not hold; see docs/serve.md, QoS and the vehicle network)"
              << std::endl;
          lost_reported[name] = s.counters.samples_lost;
          last_loss_warning = now;
        }
      }
      if (options.max_run_s > 0 && std::chrono::duration<double>(now - start).count() > options.max_run_s) break;
      if (options.status_every_s > 0 && std::chrono::duration<double>(now - last_status).count() > options.status_every_s) {
        last_status = now;
        for (const auto& [name, s] : statuses) {
          out << "  vehicle '" << name << "': " << s.counters.parts_received << " samples, " << s.frames_processed
              << " frames processed, " << s.counters.dropped_incomplete << " incomplete, "
              << s.counters.dropped_queue_full << " dropped (backlog full), "
              << s.counters.samples_lost << " lost, " << s.counters.frames_missing << " missing, "
              << s.counters.rejected_invalid << " rejected"
              << (s.quiet ? ", quiet (another serve publishes it)" : "")
              << (s.counters.last_rejection.empty() ? "" : " (last: ")
              << s.counters.last_rejection << (s.counters.last_rejection.empty() ? "" : ")") << std::endl;
          if (!s.latency.empty())
            out << "    latency ms (median/p99): " << FormatLatencyLine(s.latency) << std::endl;
        }
      }
    }
    out << "dslam serve: stopping (a second SIGINT or SIGTERM drops the frames still waiting)" << std::endl;
    // A second signal while the backlog drains: drop it; the frames in progress finish and what was
    // estimated is written as on a normal stop.
    std::atomic<bool> shut_down{false};
    std::thread second_signal([&] {
      while (!shut_down) {
        if (g_stop_signals >= 2) {
          node.abandonBacklogs();
          return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    });
    try {
      node.shutdown(out);
    } catch (...) {
      shut_down = true;
      second_signal.join();
      throw;
    }
    shut_down = true;
    second_signal.join();
    return 0;
  } catch (const std::invalid_argument& e) {  // options that contradict the profiles
    err << "dslam serve: error: " << e.what() << std::endl;
    return 2;
  } catch (const std::exception& e) {
    err << "dslam serve: error: " << e.what() << std::endl;
    return 4;
  }
}

int RunPublishCommand(const PublishCommandOptions& options, std::ostream& out, std::ostream& err) {
  InstallStopHandlers();
  try {
    if (const std::string bad = FindInvalidVehicleName(options.publish.vehicle); !bad.empty())
      throw std::invalid_argument(bad);
    ImageDatasetOptions dataset_options = options.config_path ? LoadRunConfig(*options.config_path).dataset
                                                              : ImageDatasetOptions{};
    dataset_options.sequence = options.sequence;
    dataset_options.read_flow = false;  // flow is not sent
    PublishOptions publish = options.publish;
    const auto compression = ParseImageCompression(options.compress);
    if (!compression) throw std::invalid_argument("--compress must be none, png or jpeg, got '" + options.compress + "'");
    publish.compression = *compression;
    const ImageDataset dataset(options.dataset_dir, dataset_options);
    out << "dslam publish: " << dataset.size() << " frames of " << options.dataset_dir << " at "
        << options.publish.rate_hz << " Hz on domain " << options.publish.domain_id << std::endl;
    const int n = PublishDataset(dataset, publish, out, &g_stop);
    out << "dslam publish: " << n << " frames published" << std::endl;
    return 0;
  } catch (const DdsStartError& e) {
    err << "dslam publish: error: " << e.what() << std::endl;
    return 4;
  } catch (const std::exception& e) {
    err << "dslam publish: error: " << e.what() << std::endl;
    return 2;
  }
}

int RunListenCommand(const ListenCommandOptions& options, std::ostream& out, std::ostream& err) {
  try {
    if (const std::string bad = FindInvalidVehicleName(options.vehicle); !bad.empty()) throw std::invalid_argument(bad);
    if (!std::isfinite(options.frame_rate_hz) || options.frame_rate_hz < 1e-3 || options.frame_rate_hz > 1000.0)
      throw std::invalid_argument("--rate must be between 0.001 and 1000 Hz, got " + std::to_string(options.frame_rate_hz));
    for (const auto& [name, value] : {std::pair<const char*, double>{"--max-run", options.max_run_s},
                                      {"--idle-stop", options.idle_stop_s}, {"--status-every", options.status_every_s}})
      if (!std::isfinite(value) || value < 0.0 || value > 1e9)
        throw std::invalid_argument(std::string(name) + " must be between 0 and 1e9 s, got " + std::to_string(value));
    if (options.frames < 0) throw std::invalid_argument("--frames must be 0 (no limit) or more");
  } catch (const std::exception& e) {
    err << "dslam listen: error: " << e.what() << std::endl;
    return 2;
  }
  InstallStopHandlers();
  const std::string csv_path = (std::filesystem::path(options.out_dir) / "estimates.csv").string();
  try {
    std::filesystem::create_directories(options.out_dir);
    WholeLineFile csv(csv_path);
    if (!csv) throw std::runtime_error("cannot write " + csv_path);
    csv << "stamp_ns,received_unix_ns,latency_ms,writer,x,y,z,qx,qy,qz,qw\n";
    std::mutex mutex;  // the receive thread writes, the main thread reads the totals
    EstimateStreamStats stats(options.frame_rate_hz);
    csv << std::setprecision(9);
    CameraEstimateListener listener(options.domain_id, options.profiles_file, options.vehicle,
                                    [&](const ReceivedEstimate& e) {
                                      std::lock_guard<std::mutex> lock(mutex);
                                      if (!csv.is_open()) return;  // stopping: the totals are final
                                      const double latency_ms = stats.add(e);
                                      const Vec3 t = e.T_world_camera.translation();
                                      const Eigen::Quaterniond q = e.T_world_camera.rotation();
                                      csv << e.stamp_ns << ',' << e.received_unix_ns << ',';
                                      if (latency_ms >= 0.0) csv << latency_ms;
                                      csv << ',' << e.writer << ',' << t.x() << ',' << t.y() << ',' << t.z() << ','
                                          << q.x() << ',' << q.y() << ',' << q.z() << ',' << q.w() << '\n';
                                      csv.flush();
                                    });
    out << "dslam listen: vehicle '" << options.vehicle << "' on domain " << options.domain_id << ", estimates to "
        << csv_path << " (SIGINT or SIGTERM to stop)" << std::endl;
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto last_status = start, last_arrival = start;
    uint64_t seen = 0;
    int matched = 0, alive = -1;
    const auto seconds_since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    while (!g_stop) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      uint64_t frames = 0;
      std::string line;
      {
        std::lock_guard<std::mutex> lock(mutex);
        frames = stats.distinctStamps();
        if (stats.received() != seen) seen = stats.received(), last_arrival = Clock::now();
        if (options.status_every_s > 0 && seconds_since(last_status) > options.status_every_s) line = stats.line();
      }
      if (!line.empty()) out << "  " << line << std::endl, last_status = Clock::now();
      if (const int now_matched = listener.matchedWriters(); now_matched != matched) {
        matched = now_matched;  // said as it changes: a script can wait for it before starting the sensors
        out << "dslam listen: " << matched << (matched == 1 ? " writer" : " writers") << " of estimates matched" << std::endl;
      }
      if (const int now_alive = listener.aliveWriters(); now_alive != alive && now_alive >= 0) {
        alive = now_alive;
        out << "dslam listen: " << alive << (alive == 1 ? " writer" : " writers") << " of estimates alive" << std::endl;
      }
      if (options.frames > 0 && frames >= static_cast<uint64_t>(options.frames)) break;
      if (options.max_run_s > 0 && seconds_since(start) > options.max_run_s) break;
      if (options.idle_stop_s > 0 && seen > 0 && seconds_since(last_arrival) > options.idle_stop_s) break;
    }
    std::lock_guard<std::mutex> lock(mutex);  // held until the end: no estimate is half-written
    csv.close();
    if (!csv) throw std::runtime_error("error while writing " + csv_path);
    WholeFile summary((std::filesystem::path(options.out_dir) / "listen.json").string());
    summary << stats.json().dump(2) << "\n";
    summary.commit();
    out << "dslam listen: " << stats.line() << std::endl;
    return 0;
  } catch (const std::exception& e) {
    err << "dslam listen: error: " << e.what() << std::endl;
    return 4;
  }
}

}  // namespace dslam
