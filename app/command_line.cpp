#include "app/command_line.h"

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <optional>
#include <utility>
#include <vector>

#ifndef DSLAM_CORE_COMMANDS_ONLY
#include "app/dds_commands.h"
#include "app/figures_command.h"
#endif
#include "app/full_binary.h"
#include "app/kitti_replay_command.h"
#include "app/lidar_check_command.h"
#ifndef DSLAM_CORE_COMMANDS_ONLY
#include "app/render_scene_command.h"
#include "app/study_command.h"
#endif
#include "app/run_command.h"
#include "app/sim_command.h"
#include "output/dir_lock.h"
#include "simulation/scenarios.h"

namespace {
// An output folder: a path that is not an existing file (a folder that exists, or one to be made).
const CLI::Validator kOutputDir(
    [](std::string& path) {
      std::error_code ec;
      if (std::filesystem::exists(path, ec) && !std::filesystem::is_directory(path, ec))
        return path + " is a file, not a folder to write results into";
      return std::string();
    },
    "DIR");

void AddFigureFlags(CLI::App* cmd, dslam::CommonRunOptions* options) {
  cmd->add_flag("--no-figures", options->no_figures, "Do not draw the figures and report.html at the end");
  cmd->add_option("--figure-scale", options->figure_scale, "Scale of those figures (see dslam figures --scale)")
      ->check(CLI::Range(0.1, 8.0))
      ->capture_default_str();
}
}  // namespace

namespace dslam {

int RunCommandLine(int argc, char** argv) {
  CLI::App app{"dslam: object-aware dynamic SLAM (Henein et al., ICRA 2020) - simulate, run and evaluate"};
  app.require_subcommand(1);

  dslam::SimCommandOptions sim;
  CLI::App* sim_cmd = app.add_subcommand(
      "sim", "Simulate a scenario, run ours, static-only and SLAM+MOT, write results and print the metrics table");
  sim_cmd->add_option("--scenario", sim.scenario, "Scenario: paper (one ellipsoid, circular path), city or crossing (a junction)")
      ->check(CLI::IsMember(dslam::ScenarioNames()))
      ->capture_default_str();
  sim_cmd->add_option("--seed", sim.seed, "Random seed (noise and scene); runs are deterministic")->capture_default_str();
  sim_cmd->add_option("--mode", sim.mode,
                      "Object motion model: per-step, constant or smoothed (default: constant for paper, smoothed "
                      "for city and crossing)");
  sim_cmd->add_option("--schedule", sim.schedule,
                      "Solver schedule: " + dslam::ToString(dslam::DefaultsOf(dslam::EntryPoint::kSim).schedule) +
                          " (default) or window:W with W >= 2");
  sim_cmd->add_option("--sigma", sim.sigma_m, "Point measurement noise sigma per axis, metres (0.0001 to 10)")
      ->check(CLI::Range(1e-4, 10.0))
      ->capture_default_str();
  sim_cmd->add_option("--frames", sim.frames, "Number of frames (0: the scenario's default, 100 / 200; at most 100000)")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  sim_cmd->add_option("--config", sim.config_path, "YAML run configuration (see config/default.yaml)")
      ->check(CLI::ExistingFile);
  sim_cmd->add_option("--out", sim.out_dir, "Output directory")->check(kOutputDir)->capture_default_str();
  sim_cmd->add_flag("--quiet", sim.quiet, "Print only errors");
  AddFigureFlags(sim_cmd, &sim);

  dslam::KittiReplayCommandOptions replay;
  CLI::App* replay_cmd = app.add_subcommand(
      "kitti-replay",
      "Replay a KITTI tracking sequence's real camera path and object boxes with synthetic measurements; run and "
      "evaluate ours, static-only and SLAM+MOT");
  replay_cmd->add_option("--data", replay.data_dir, "Dataset directory (KITTI layout or VDO-SLAM layout)")
      ->required()
      ->check(CLI::ExistingDirectory);
  replay_cmd->add_option("--seq", replay.sequence, "Sequence number, e.g. 0000")->required();
  replay_cmd->add_option("--sigma", replay.sigma_m, "Point noise sigma per axis, metres (0.02, 0.04, 0.06; 0.0001 to 10)")
      ->check(CLI::Range(1e-4, 10.0))
      ->capture_default_str();
  replay_cmd->add_option("--seed", replay.seed, "Random seed; runs are deterministic")->capture_default_str();
  replay_cmd->add_option("--mode", replay.mode,
                         std::string("Object motion model: per-step, constant or smoothed (default ") +
                             dslam::ToString(dslam::DefaultsOf(dslam::EntryPoint::kKittiReplay).mode) + ")");
  replay_cmd->add_option("--schedule", replay.schedule,
                         "Solver schedule: " +
                             dslam::ToString(dslam::DefaultsOf(dslam::EntryPoint::kKittiReplay).schedule) +
                             " (default) or window:W");
  replay_cmd->add_option("--category", replay.category,
                         "Object category the metrics cover (VEHICLE, PEDESTRIAN, BICYCLE; empty = all)")
      ->capture_default_str();
  replay_cmd->add_option("--config", replay.config_path, "YAML run configuration")->check(CLI::ExistingFile);
  replay_cmd->add_option("--out", replay.out_dir, "Output directory")->check(kOutputDir)->capture_default_str();
  replay_cmd->add_flag("--quiet", replay.quiet, "Print only errors");
  AddFigureFlags(replay_cmd, &replay);

#ifndef DSLAM_CORE_COMMANDS_ONLY
  std::string figures_dir;
  dslam::FigureOptions figures;
  CLI::App* figures_cmd = app.add_subcommand(
      "figures", "Draw trajectory.png, speeds.png, errors.png, map.png and report.html from a run's result files "
                 "(starts its own Xvfb when DISPLAY is unset)");
  figures_cmd->add_option("RESULTS_DIR", figures_dir, "Directory written by dslam sim / kitti-replay")
      ->required()
      ->check(CLI::ExistingDirectory);
  figures_cmd->add_option("--scale", figures.scale, "Multiplies size, fonts and line widths (print resolution)")
      ->check(CLI::Range(0.1, 8.0))
      ->capture_default_str();
  figures_cmd->add_option("--width", figures.width, "Width in pixels at scale 1")->check(CLI::Range(200, 8000))->capture_default_str();
  figures_cmd->add_option("--height", figures.height, "Height in pixels at scale 1")->check(CLI::Range(150, 8000))->capture_default_str();
  // Hidden: a run's figures, drawn by its child (app/full_binary.h) into the folder the run holds.
  bool figures_for_parent = false;
  figures_cmd->add_flag("--for-parent", figures_for_parent, "")->group("");

#endif
  dslam::LidarCheckCommandOptions lidar_check;
  CLI::App* lidar_check_cmd = app.add_subcommand(
      "lidar-check", "LiDAR-only reference of a recording (ego-motion from scan registration, each cluster's speed) "
                     "and, with --run, a run on it checked against that reference");
  lidar_check_cmd->add_option("--dataset", lidar_check.dataset_dir, "Recording with LiDAR scans (kitti-raw layout: "
                                                                    "image_02/, velodyne_points/, calib.txt)")
      ->required()
      ->check(CLI::ExistingDirectory);
  lidar_check_cmd->add_option("--run", lidar_check.run_dir, "Result folder of a dslam run on that recording")
      ->check(CLI::ExistingDirectory);
  lidar_check_cmd->add_option("--config", lidar_check.config_path,
                              "The run's YAML configuration (its masks.lidar_* keys shape the clusters)")
      ->check(CLI::ExistingFile);
  lidar_check_cmd->add_option("--frames", lidar_check.frames, "Scans to use (0: all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  lidar_check_cmd->add_option("--out", lidar_check.out_dir, "Output directory")->check(kOutputDir)->capture_default_str();
  lidar_check_cmd->add_flag("--quiet", lidar_check.quiet, "Print only the results and errors");

#ifndef DSLAM_CORE_COMMANDS_ONLY
  dslam::RenderSceneOptions render;
  CLI::App* render_cmd = app.add_subcommand(
      "render-scene", "Render a KITTI-driven RGB-D scene (colour, depth, instance masks, exact ground truth) in the "
                      "VDO-SLAM layout; starts its own Xvfb when DISPLAY is unset");
  auto* kitti_opt = render_cmd
                        ->add_option("--kitti", render.kitti_dir,
                                     "KITTI tracking data directory (KITTI or VDO-SLAM layout), with --seq")
                        ->check(CLI::ExistingDirectory);
  render_cmd->add_option("--seq", render.sequence, "Sequence number, e.g. 0000")->needs(kitti_opt);
  render_cmd->add_option("--scenario", render.scenario, "Or a simulator scenario with box objects: city or crossing")
      ->excludes(kitti_opt)
      ->check(CLI::IsMember({"city", "crossing"}));
  render_cmd->add_option("--frames", render.frames, "Frames to render (0: all; a scenario's default length)")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  render_cmd->add_option("--scale", render.scale, "Image size relative to 1242x375, intrinsics scaled alike (0.05 to 4)")
      ->check(CLI::Range(0.05, 4.0))
      ->capture_default_str();
  render_cmd->add_option("--image-noise", render.image_noise, "Colour noise sigma, grey levels (0 to 255)")
      ->check(CLI::Range(0.0, 255.0))
      ->capture_default_str();
  render_cmd->add_option("--depth-noise", render.depth_noise_m, "Depth noise sigma at zero depth, metres (0 to 10)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  render_cmd->add_option("--depth-noise-per-m2", render.depth_noise_per_m2,
                         "Depth noise sigma added per square metre of depth (0 to 1)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  render_cmd->add_option("--seed", render.seed, "Seed of the noise")->capture_default_str();
  render_cmd->add_flag("--stereo", render.stereo,
                       "Also render the right camera (image_1/, KITTI's 0.54 m baseline, P3 in calib.txt)");
  render_cmd->add_flag("--exact-flow", render.exact_flow,
                       "Also write the exact forward flow (flow/NNNNNN.flo, ~3.7 MB a 1242x375 frame)");
  render_cmd->add_option("--out", render.out_dir, "Output directory")->check(kOutputDir)->capture_default_str();
  render_cmd->add_flag("--quiet", render.quiet, "Print only errors and the summary");

#endif
  dslam::RunCommandOptions run;
  CLI::App* run_cmd = app.add_subcommand(
      "run", "Run the image front-end and the back-end on a recorded or rendered image sequence (VDO-SLAM / DynoSAM "
             "layout, KITTI tracking or KITTI raw); evaluate ours, static-only and SLAM+MOT when it has ground truth");
  run_cmd->add_option("--dataset", run.dataset_dir, "Dataset directory (see docs/run.md, Datasets)")
      ->required()
      ->check(CLI::ExistingDirectory);
  run_cmd->add_option("--seq", run.sequence, "KITTI tracking layout: sequence number, e.g. 0000");
  run_cmd->add_option("--flow", run.flow,
                      "Point tracking: optical flow lk, dis or precomputed, or orb descriptor matching "
                      "(default: frontend.flow_method, lk)")
      ->check(CLI::IsMember({"lk", "dis", "precomputed", "orb"}));
  run_cmd->add_option("--frames", run.frames, "Use only the first N frames (0: all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  run_cmd->add_option("--mode", run.mode,
                      std::string("Object motion model: per-step, constant or smoothed (default ") +
                          dslam::ToString(dslam::DefaultsOf(dslam::EntryPoint::kRun).mode) + ")");
  run_cmd->add_option("--schedule", run.schedule,
                      "Solver schedule: window:W (default " +
                          dslam::ToString(dslam::DefaultsOf(dslam::EntryPoint::kRun).schedule) + ") or batch");
  run_cmd->add_option("--sigma", run.sigma_m, "Point measurement sigma per axis assumed by the back-end, metres (0.0001 to 10)")
      ->check(CLI::Range(1e-4, 10.0))
      ->capture_default_str();
  run_cmd->add_option("--category", run.category, "Object category the metrics cover (empty = all)")
      ->capture_default_str();
  run_cmd->add_option("--methods", run.methods, "Methods to run: ours, static_only, slam_mot (default: all three)")
      ->check(CLI::IsMember({"ours", "static_only", "slam_mot"}))
      ->delimiter(',')
      ->capture_default_str();
  run_cmd->add_option("--config", run.config_path, "YAML run configuration (see config/default.yaml)")
      ->check(CLI::ExistingFile);
  run_cmd->add_option("--out", run.out_dir, "Output directory")->check(kOutputDir)->capture_default_str();
  run_cmd->add_flag("--quiet", run.quiet, "Print only errors");
  AddFigureFlags(run_cmd, &run);

#ifndef DSLAM_CORE_COMMANDS_ONLY
  dslam::StudyCommandOptions study;
  CLI::App* study_cmd = app.add_subcommand(
      "study", "The paper's front-end study on a rendered scene (render-scene --stereo --exact-flow): depth, "
               "segmentation and tracking made realistic one at a time; writes study.csv, tracking.csv and figures");
  study_cmd->add_option("--dataset", study.dataset_dir, "Rendered scene with the stereo pair and the exact flow")
      ->required()
      ->check(CLI::ExistingDirectory);
  study_cmd->add_option("--frames", study.frames, "Use only the first N frames (0: all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  study_cmd->add_option("--config", study.config_path, "YAML run configuration (see config/default.yaml)")
      ->check(CLI::ExistingFile);
  study_cmd->add_option("--seed", study.seed, "Seed of the depth noise and of the degraded segmenter")
      ->capture_default_str();
  study_cmd->add_option("--out", study.out_dir, "Output directory")->check(kOutputDir)->capture_default_str();
  study_cmd->add_flag("--quiet", study.quiet, "Print only errors and the summary");
  AddFigureFlags(study_cmd, &study);

  dslam::ServeCommandOptions serve;
  CLI::App* serve_cmd = app.add_subcommand(
      "serve", "Run as a Fast DDS participant: read colour, depth, masks and odometry, publish camera odometry, "
               "object motions and status per frame; on SIGINT/SIGTERM write the results");
  serve_cmd->add_option("--calib", serve.calib_path, "Camera calibration, KITTI calib.txt format (P2, else P0)")
      ->required()
      ->check(CLI::ExistingFile);
  serve_cmd->add_option("--vehicle", serve.vehicles,
                        "Vehicle topic namespace (rt/NAME/camera/...); repeat for several (default: none)");
  // 0..232: the highest domain id whose RTPS ports fit in UDP's port range.
  serve_cmd->add_option("--domain", serve.domain_id, "DDS domain id (0-232)")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  serve_cmd->add_option("--profiles", serve.profiles_file, "Fast DDS XML profiles (QoS, transports, security)")
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  serve_cmd->add_option("--config", serve.config_path, "YAML run configuration")->check(CLI::ExistingFile);
  serve_cmd->add_option("--out", serve.out_dir, "Results directory (one folder per vehicle)")
      ->check(kOutputDir)
      ->capture_default_str();
  serve_cmd->add_flag("--no-odometry", serve.no_odometry, "Do not wait for odometry with every frame");
  serve_cmd->add_option("--rate", serve.frame_rate_hz, "Sensor frame rate (Hz): a step over 1.5 periods is a gap (frames dropped); speeds use the stamps (0.001 to 1000)")
      ->check(CLI::Range(0.001, 1000.0))
      ->capture_default_str();
  serve_cmd->add_option("--timeout-ms", serve.timeout_ms,
                        "An incomplete frame set this far (stamps) behind the newest one is dropped")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  serve_cmd->add_option("--silence-ms", serve.silence_ms,
                        "When no sample arrives for this long (wall time), incomplete frame sets are dropped")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  serve_cmd->add_option("--max-pending", serve.max_pending,
                        "Frame sets held for assembly (and with --every-frame while the pipeline is busy), 1 to 64; beyond, the oldest is dropped and counted")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  serve_cmd->add_option("--max-pending-mb", serve.max_pending_mb,
                        "At most this many MiB of pixels in those sets (16 to 8192); beyond, the oldest is dropped")
      ->check(CLI::Range(16, 8192))
      ->capture_default_str();
  serve_cmd->add_flag("--every-frame", serve.every_frame,
                      "Estimate every assembled frame however late (replays); by default, when serve falls behind, "
                      "the newest frame wins and older waiting frames are dropped (counted, their odometry carried on)");
  serve_cmd->add_option("--status-every", serve.status_every_s, "Console status period, s (0: never; at most 86400)")
      ->check(CLI::Range(0.0, 86400.0))
      ->capture_default_str();
  serve_cmd->add_option("--max-run", serve.max_run_s, "Stop by itself after this many seconds (0: never; at most 1e9)")
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();
  serve_cmd->add_option("--node-name", serve.node_name,
                        "ROS 2 node name shown by `ros2 node list`, one per vehicle in its namespace")
      ->capture_default_str();
  serve_cmd->add_option("--ros-distro", serve.ros_distro,
                        "ROS 2 distribution of the graph's GID layout: humble (24 octets; also foxy, galactic) or "
                        "jazzy (16; also iron, kilted, lyrical, rolling)")
      ->capture_default_str();

  serve_cmd->add_option("--fleet-share", serve.fleet_share,
                        "K/N: this is serve host K (0..N-1) of N given the same --vehicle list; it serves the "
                        "vehicles at places K, K+N, ... of the list sorted by name, so each has one host");
  serve_cmd->add_option("--ownership-strength", serve.ownership_strength,
                        "Hot standby: this instance's ownership strength on its outputs; with a profile of EXCLUSIVE "
                        "ownership subscribers follow the live serve of highest strength (-1: the profile's)")
      ->check(CLI::Range(-1, 2147483647))
      ->capture_default_str();

  dslam::PublishCommandOptions publish;
  CLI::App* publish_cmd = app.add_subcommand(
      "publish", "Replay a recorded or rendered sequence onto a vehicle's input topics, as its sensors would");
  publish_cmd->add_option("--dataset", publish.dataset_dir, "Dataset directory (as dslam run)")
      ->required()
      ->check(CLI::ExistingDirectory);
  publish_cmd->add_option("--seq", publish.sequence, "KITTI tracking layout: sequence number");
  publish_cmd->add_option("--config", publish.config_path,
                          "YAML run configuration: its dataset section reads the dataset as dslam run does "
                          "(depth encoding, LiDAR fill radius)")
      ->check(CLI::ExistingFile);
  publish_cmd->add_option("--rate", publish.publish.rate_hz, "Frames per second (0.001 to 1000)")
      ->check(CLI::Range(0.001, 1000.0))
      ->capture_default_str();
  publish_cmd->add_option("--vehicle", publish.publish.vehicle, "Vehicle topic namespace (default: none)");
  publish_cmd->add_option("--domain", publish.publish.domain_id, "DDS domain id (0-232)")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  publish_cmd->add_option("--profiles", publish.publish.profiles_file, "Fast DDS XML profiles")
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  publish_cmd->add_option("--start-frame", publish.publish.start_frame, "First frame (resume a replay)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  publish_cmd->add_option("--frames", publish.publish.frames, "Frames to publish (0: to the end)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  publish_cmd->add_option("--wait", publish.publish.wait_for_reader_s, "Seconds to wait for a reader first (0 to 3600)")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  publish_cmd->add_option("--compress", publish.compress,
                          "Images as sensor_msgs/CompressedImage on <topic>/compressed: png (lossless) or jpeg (colour; "
                          "depth and mask stay png), for links that cannot carry raw images; none: raw Image")
      ->check(CLI::IsMember({"none", "png", "jpeg"}))
      ->capture_default_str();
  publish_cmd->add_flag("--preload", publish.publish.preload,
                        "Read and encode every frame before sending the first (a camera host that encodes in hardware: "
                        "nothing to do per frame but send); holds them all in memory");
  publish_cmd->add_flag("--stamp-now", publish.publish.stamp_now,
                        "Stamp each frame with this host's clock as it is published (as a camera driver does), not the "
                        "dataset's times: latency from capture can then be measured downstream");

  dslam::ListenCommandOptions listen;
  CLI::App* listen_cmd = app.add_subcommand(
      "listen", "Subscribe to a vehicle's estimates as another host would: each camera estimate with its writer and "
                "latency to a CSV, repeated and missing frames counted");
  listen_cmd->add_option("--vehicle", listen.vehicle, "Vehicle topic namespace (default: none)");
  listen_cmd->add_option("--domain", listen.domain_id, "DDS domain id (0-232)")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  listen_cmd->add_option("--profiles", listen.profiles_file, "Fast DDS XML profiles")
      ->check(CLI::ExistingFile)
      ->capture_default_str();
  listen_cmd->add_option("--out", listen.out_dir, "Output directory (estimates.csv, listen.json)")
      ->check(kOutputDir)
      ->capture_default_str();
  listen_cmd->add_option("--rate", listen.frame_rate_hz,
                         "Sensor frame rate (Hz): frames missing between stamps are counted at it (0.001 to 1000)")
      ->check(CLI::Range(0.001, 1000.0))
      ->capture_default_str();
  listen_cmd->add_option("--frames", listen.frames, "Stop after this many frames (0: no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  listen_cmd->add_option("--max-run", listen.max_run_s, "Stop after this many seconds (0: never; at most 1e9)")
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();
  listen_cmd->add_option("--idle-stop", listen.idle_stop_s,
                         "Stop when no estimate arrived for this many seconds since the last one (0: never)")
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();
  listen_cmd->add_option("--status-every", listen.status_every_s, "Console status period, s (0: never)")
      ->check(CLI::Range(0.0, 86400.0))
      ->capture_default_str();

#endif
  // An unknown command is named (CLI11 would only say that one is required).
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
      known = known || sub->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::cerr << "dslam: unknown command '" << argv[1] << "' (commands: " << names << ")" << std::endl;
      return 2;
    }
  }
  // Bad options exit with status 2, as every other bad input (CLI11's own codes are 105-109).
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  // A --sigma left at its default must not override a configuration file's point_sigma_m.
  sim.sigma_given = sim_cmd->count("--sigma") > 0;
  replay.sigma_given = replay_cmd->count("--sigma") > 0;
  run.sigma_given = run_cmd->count("--sigma") > 0;
  // A command's output folder is its own while it runs (output/dir_lock.h): a second command writing the same
  // folder stops with status 4 instead of interleaving its files. (serve takes each vehicle's folder itself;
  // figures only a folder that exists: a missing one is bad input, said by the command.)
  std::optional<dslam::DirLock> out_lock;
  std::vector<std::pair<CLI::App*, std::string>> writers = {
      {run_cmd, run.out_dir}, {sim_cmd, sim.out_dir}, {replay_cmd, replay.out_dir},
      {lidar_check_cmd, lidar_check.out_dir}};
#ifndef DSLAM_CORE_COMMANDS_ONLY
  writers.insert(writers.end(), {{study_cmd, study.out_dir}, {render_cmd, render.out_dir}, {listen_cmd, listen.out_dir}});
  // A run's child drawing its figures does not take the folder its parent holds (if that is who holds it).
  if (!figures_for_parent || !std::filesystem::is_directory(figures_dir) ||
      dslam::FolderHolderPid(figures_dir) != ::getppid())
    writers.push_back({figures_cmd, std::filesystem::is_directory(figures_dir) ? figures_dir : std::string()});
#endif
  for (const auto& [cmd, dir] : writers) {
    if (!cmd->parsed() || dir.empty()) continue;
    try {
      out_lock.emplace(dir);
    } catch (const dslam::FolderInUseError& e) {
      std::cerr << "dslam " << cmd->get_name() << ": error: " << e.what() << std::endl;
      return 4;
    } catch (const std::exception& e) {
      std::cerr << "dslam " << cmd->get_name() << ": error: " << e.what() << std::endl;
      return 2;
    }
  }
  if (run_cmd->parsed()) return dslam::RunRunCommand(run, std::cout, std::cerr);
  if (sim_cmd->parsed()) return dslam::RunSimCommand(sim, std::cout, std::cerr);
  if (replay_cmd->parsed()) return dslam::RunKittiReplayCommand(replay, std::cout, std::cerr);
  if (lidar_check_cmd->parsed()) return dslam::RunLidarCheckCommand(lidar_check, std::cout, std::cerr);
#ifdef DSLAM_CORE_COMMANDS_ONLY
  // dslam hands the other commands to dslam-full before parsing (main.cpp); this is for a caller that did not.
  out_lock.reset();
  return dslam::ExecFullBinary(argv, std::cerr);
#else
  if (serve_cmd->parsed()) return dslam::RunServeCommand(serve, std::cout, std::cerr);
  if (publish_cmd->parsed()) return dslam::RunPublishCommand(publish, std::cout, std::cerr);
  if (listen_cmd->parsed()) return dslam::RunListenCommand(listen, std::cout, std::cerr);
  if (study_cmd->parsed()) return dslam::RunStudyCommand(study, std::cout, std::cerr);
  if (render_cmd->parsed()) return dslam::RunRenderSceneCommand(render, std::cout, std::cerr);
  if (figures_cmd->parsed()) return dslam::RunFiguresCommand(figures_dir, figures, std::cout, std::cerr);
  return 0;
#endif
}

}  // namespace dslam
