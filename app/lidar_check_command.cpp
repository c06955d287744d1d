#include "app/lidar_check_command.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "data/image_dataset.h"
#include "lidar/lidar_comparison.h"
#include "lidar/lidar_reference.h"
#include "output/result_reader.h"
#include "output/text_format.h"
#include "output/trajectory_io.h"
#include "output/whole_file.h"
#include "pipeline/config_yaml.h"

namespace dslam {
namespace {

void WriteWholeFile(const std::string& path, const std::string& text) {
  WholeFile f(path);
  f << text;
  f.commit();
}

std::string Fixed(double v, int precision) { return FormatFixed(v, precision, "-"); }

void WriteTracks(const std::string& path, const LidarReference& reference) {
  std::ostringstream s;
  s << std::setprecision(9);
  s << "frame,track_id,points,extent_m,centroid_x_m,centroid_y_m,centroid_z_m,speed_mps,box_x,box_y,box_w,box_h\n";
  for (const LidarTrackSample& t : reference.samples) {
    s << t.frame << ',' << t.track_id << ',' << t.points << ',' << t.extent_m << ',' << t.centroid_camera.x() << ','
      << t.centroid_camera.y() << ',' << t.centroid_camera.z() << ',';
    if (t.has_speed) s << t.speed_mps;
    s << ',' << t.box.x << ',' << t.box.y << ',' << t.box.width << ',' << t.box.height << '\n';
  }
  WriteWholeFile(path, s.str());
}

nlohmann::json ToJson(const LidarCheckReport& r) {
  nlohmann::json j;
  j["frames"] = r.frames;
  j["camera"] = {{"path_length_m", r.path_length_m},     {"end_error_m", r.end_error_m},
                 {"end_error_pct", r.end_error_pct},     {"rte_pct", r.rte_pct},
                 {"rre_deg_per_m", r.rre_deg_per_m},     {"mean_step_rotation_error_deg", r.mean_step_rotation_error_deg}};
  j["reference_noise"] = {{"median_step_disagreement_m", r.reference_noise.median_step_m},
                          {"summed_pct_of_path", r.reference_noise.summed_pct_of_path}};
  j["vehicles"] = nlohmann::json::array();
  for (const auto& v : r.vehicles) {
    nlohmann::json o = {{"lidar_track_id", v.track_id},
                        {"frames", v.frames},
                        {"frames_with_speed", v.frames_with_speed},
                        {"coverage", v.coverage},
                        {"median_lidar_speed_mps", v.median_lidar_speed_mps},
                        {"moving_while_standing_frames", v.moving_while_standing}};
    o["median_speed_difference_mps"] = v.median_speed_difference_mps ? nlohmann::json(*v.median_speed_difference_mps) : nlohmann::json();
    j["vehicles"].push_back(o);
  }
  j["moving_rows"] = r.moving_rows;
  j["moving_rows_without_cluster"] = r.moving_rows_without_cluster;
  j["moving_rows_on_standing_cluster"] = r.moving_rows_on_standing;
  return j;
}

}  // namespace

int RunLidarCheckCommand(const LidarCheckCommandOptions& options, std::ostream& out, std::ostream& err) {
  try {
    if (options.frames < 0) throw std::invalid_argument("--frames must be >= 0");
    const RunConfig config = options.config_path.empty() ? RunConfig{} : LoadRunConfig(options.config_path);
    ImageDatasetOptions dataset_options = config.dataset;
    dataset_options.read_flow = false;
    const ImageDataset dataset(options.dataset_dir, dataset_options);
    if (!dataset.hasLidar())
      throw std::invalid_argument(options.dataset_dir + " has no LiDAR scans (expected velodyne_points/)");
    std::error_code ec;
    std::filesystem::create_directories(options.out_dir, ec);
    if (ec) throw std::invalid_argument("cannot create output directory " + options.out_dir + ": " + ec.message());

    LidarReferenceParams params;
    params.clusters = config.masks.lidar;
    params.frame_interval_s = 1.0 / dataset.frameRateHz();
    LidarReferenceBuilder builder(params, dataset.camera());
    const int frames = options.frames > 0 ? std::min(options.frames, dataset.size()) : dataset.size();
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < frames; ++k) {
      const ImageFrame frame = dataset.read(k);
      builder.add(frame.lidar_points_camera, frame.lidar_origin_camera, frame.lidar_up_camera);
      if (!options.quiet && ((k + 1) % std::max(1, frames / 10) == 0 || k + 1 == frames)) {
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        out << "  LiDAR reference: scan " << k + 1 << "/" << frames << ", " << Fixed((k + 1) / s, 1) << " scans/s"
            << std::endl;
      }
    }
    const LidarReference reference = builder.finish();
    std::vector<int64_t> t_ns;
    for (int k = 0; k < frames; ++k) t_ns.push_back(dataset.stampNs(k));
    WriteTumTrajectory(options.out_dir + "/lidar_ego.tum", t_ns, reference.T_world_camera);
    WriteTracks(options.out_dir + "/lidar_tracks.csv", reference);
    const Vec3 end = reference.T_world_camera.back().translation();
    out << "LiDAR reference of " << options.dataset_dir << ": " << frames << " scans, the camera ends at ("
        << Fixed(end.x(), 2) << ", " << Fixed(end.y(), 2) << ", " << Fixed(end.z(), 2) << ") m; written to "
        << options.out_dir << "/lidar_ego.tum and lidar_tracks.csv" << std::endl;
    const LidarReferenceNoise noise = ReferenceNoise(reference);
    out << "Its own step noise (each scan pair registered both ways): " << Fixed(1000.0 * noise.median_step_m, 1)
        << " mm a frame (median), " << Fixed(noise.summed_pct_of_path, 2)
        << " % of the path summed: the floor under a frame-to-frame comparison" << std::endl;
    if (options.run_dir.empty()) return 0;

    const RunResults run = ReadRunResults(options.run_dir);
    std::vector<RunObjectRow> rows;
    for (const RunResults::SpeedRow& s : run.speeds) {
      if (!s.estimated) continue;
      RunObjectRow row{s.frame, s.object_id, s.is_dynamic, s.est_mps, s.centroid_camera, std::nullopt};
      if (s.box) row.box = cv::Rect((*s.box)[0], (*s.box)[1], (*s.box)[2], (*s.box)[3]);
      rows.push_back(row);
    }
    LidarCheckParams check;
    check.image_width = dataset.camera().width, check.image_height = dataset.camera().height;
    const LidarCheckReport report = CompareWithLidar(reference, run.camera_est, rows, check);
    nlohmann::json j = ToJson(report);
    j["dataset"] = options.dataset_dir;
    j["run"] = options.run_dir;
    j["method"] = run.method;
    WriteWholeFile(options.out_dir + "/lidar_check.json", j.dump(2) + "\n");

    out << "Camera (" << run.method << ") against the LiDAR registration over " << Fixed(report.path_length_m, 2)
        << " m: end point " << Fixed(report.end_error_m, 3) << " m off (" << Fixed(report.end_error_pct, 2)
        << " % of the path), frame to frame " << Fixed(report.rte_pct, 2) << " % of the distance, rotation "
        << Fixed(report.rre_deg_per_m, 3) << " deg/m (" << Fixed(report.mean_step_rotation_error_deg, 3)
        << " deg a frame)" << std::endl;
    out << "Vehicles the LiDAR tracks for 10+ frames within 25 m: " << report.vehicles.size() << std::endl;
    out << "  track  frames  with speed  coverage  LiDAR median m/s  median |diff| m/s  moving while standing" << std::endl;
    for (const auto& v : report.vehicles) {
      char line[200];
      std::snprintf(line, sizeof line, "  %5d  %6d  %10d  %8.2f  %16.2f  %17s  %21d", v.track_id, v.frames,
                    v.frames_with_speed, v.coverage, v.median_lidar_speed_mps,
                    FormatFixed(v.median_speed_difference_mps, 2, "-").c_str(),
                    v.moving_while_standing);
      out << line << std::endl;
    }
    out << "Rows reported moving: " << report.moving_rows << ", at no LiDAR cluster: " << report.moving_rows_without_cluster
        << ", at a standing cluster: " << report.moving_rows_on_standing << std::endl;
    out << "Written to " << options.out_dir << "/lidar_check.json" << std::endl;
    return 0;
  } catch (const std::exception& e) {
    err << "dslam lidar-check: error: " << e.what() << std::endl;
    return 2;
  }
}

}  // namespace dslam
