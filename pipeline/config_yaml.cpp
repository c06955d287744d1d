#include "pipeline/config_yaml.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <type_traits>

namespace dslam {
namespace {
// One binding per configurable scalar: how to read it from a YAML node and write it back.
struct Binding {
  std::function<void(const YAML::Node&, RunConfig&)> read;
  std::function<void(YAML::Emitter&, const RunConfig&)> write;
};

template <typename T>
Binding Field(std::function<T&(RunConfig&)> ref) {
  return {[ref](const YAML::Node& n, RunConfig& c) {
            const T value = n.as<T>();
            // .inf and .nan parse as numbers; no setting means either.
            if constexpr (std::is_floating_point_v<T>)
              if (!std::isfinite(value)) throw std::invalid_argument("'" + n.Scalar() + "' is not a finite number");
            ref(c) = value;
          },
          [ref](YAML::Emitter& e, const RunConfig& c) { e << ref(const_cast<RunConfig&>(c)); }};
}

Binding ModeField(std::function<MotionMode&(RunConfig&)> ref) {
  return {[ref](const YAML::Node& n, RunConfig& c) { ref(c) = ParseMotionMode(n.as<std::string>()); },
          [ref](YAML::Emitter& e, const RunConfig& c) { e << ToString(ref(const_cast<RunConfig&>(c))); }};
}

// object id -> motion mode, e.g. {3: constant, 7: smoothed}.
Binding ObjectModesField() {
  return {[](const YAML::Node& n, RunConfig& c) {
            if (!n.IsMap() && !n.IsNull()) throw std::invalid_argument("must map object ids to motion modes");
            c.backend.mode_per_object.clear();
            for (const auto& entry : n) {
              int id = 0;
              try {
                id = entry.first.as<int>();
              } catch (const YAML::Exception&) {
                throw std::invalid_argument("object id '" + entry.first.as<std::string>() + "' is not an integer");
              }
              c.backend.mode_per_object[id] = ParseMotionMode(entry.second.as<std::string>());
            }
          },
          [](YAML::Emitter& e, const RunConfig& c) {
            e << YAML::Flow << YAML::BeginMap;
            for (const auto& [id, mode] : c.backend.mode_per_object) e << YAML::Key << id << YAML::Value << ToString(mode);
            e << YAML::EndMap;
          }};
}

Binding ScheduleField() {
  return {[](const YAML::Node& n, RunConfig& c) { c.backend.schedule = ParseSchedule(n.as<std::string>()); },
          [](YAML::Emitter& e, const RunConfig& c) { e << ToString(c.backend.schedule); }};
}

// section -> key -> binding, in the order they are written.
using Schema = std::vector<std::pair<std::string, std::vector<std::pair<std::string, Binding>>>>;

const Schema& GetSchema() {
  static const Schema schema = {
      {"backend",
       {{"motion_mode", ModeField([](RunConfig& c) -> MotionMode& { return c.backend.default_mode; })},
        {"object_modes", ObjectModesField()},
        {"slam_mot_mode", ModeField([](RunConfig& c) -> MotionMode& { return c.backend.slam_mot_mode; })},
        {"schedule", ScheduleField()},
        {"object_window_frames", Field<int>([](RunConfig& c) -> int& { return c.backend.object_window_frames; })},
        {"landmark_history_frames", Field<int>([](RunConfig& c) -> int& { return c.backend.landmark_history_frames; })},
        {"max_iterations_batch", Field<int>([](RunConfig& c) -> int& { return c.backend.max_iterations_batch; })},
        {"max_iterations_window", Field<int>([](RunConfig& c) -> int& { return c.backend.max_iterations_window; })},
        {"batch_function_tolerance",
         Field<double>([](RunConfig& c) -> double& { return c.backend.batch_function_tolerance; })},
        {"window_function_tolerance",
         Field<double>([](RunConfig& c) -> double& { return c.backend.window_function_tolerance; })},
        {"num_threads", Field<int>([](RunConfig& c) -> int& { return c.backend.num_threads; })},
        {"marginalisation",
         {[](const YAML::Node& n, RunConfig& c) { c.backend.marginalisation = ParseMarginalisation(n.as<std::string>()); },
          [](YAML::Emitter& e, const RunConfig& c) { e << ToString(c.backend.marginalisation); }}},
        {"linear_solver",
         {[](const YAML::Node& n, RunConfig& c) { c.backend.linear_solver = ParseLinearSolver(n.as<std::string>()); },
          [](YAML::Emitter& e, const RunConfig& c) { e << ToString(c.backend.linear_solver); }}}}},
      {"noise",
       {{"point_sigma_m", Field<double>([](RunConfig& c) -> double& { return c.backend.noise.point_sigma_m; })},
        {"point_sigma_per_depth_sq",
         Field<double>([](RunConfig& c) -> double& { return c.backend.noise.point_sigma_per_depth_sq; })},
        {"motion_sigma_m", Field<double>([](RunConfig& c) -> double& { return c.backend.noise.motion_sigma_m; })},
        {"smoothness_sigma_t_m",
         Field<double>([](RunConfig& c) -> double& { return c.backend.noise.smoothness_sigma_t_m; })},
        {"smoothness_sigma_r_rad",
         Field<double>([](RunConfig& c) -> double& { return c.backend.noise.smoothness_sigma_r_rad; })},
        {"prior_sigma", Field<double>([](RunConfig& c) -> double& { return c.backend.noise.prior_sigma; })},
        {"huber_delta", Field<double>([](RunConfig& c) -> double& { return c.backend.noise.huber_delta; })},
        {"smoothness_huber_delta",
         Field<double>([](RunConfig& c) -> double& { return c.backend.noise.smoothness_huber_delta; })},
        {"smoothness_from_residuals",
         Field<bool>([](RunConfig& c) -> bool& { return c.backend.noise.smoothness_from_residuals; })}}},
      {"motion_ransac",
       {{"max_iterations", Field<int>([](RunConfig& c) -> int& { return c.backend.motion_ransac.max_iterations; })},
        {"inlier_threshold_m",
         Field<double>([](RunConfig& c) -> double& { return c.backend.motion_ransac.inlier_threshold_m; })},
        {"min_inliers", Field<int>([](RunConfig& c) -> int& { return c.backend.motion_ransac.min_inliers; })}}},
      {"classifier",
       {{"dynamic_speed_threshold_mps",
         Field<double>([](RunConfig& c) -> double& { return c.classifier.dynamic_speed_threshold_mps; })},
        {"report_speed_threshold_mps",
         Field<double>([](RunConfig& c) -> double& { return c.classifier.report_speed_threshold_mps; })},
        {"static_test_chi2", Field<double>([](RunConfig& c) -> double& { return c.classifier.static_test_chi2; })},
        {"min_static_transitions",
         Field<int>([](RunConfig& c) -> int& { return c.classifier.min_static_transitions; })},
        {"min_static_inliers", Field<int>([](RunConfig& c) -> int& { return c.classifier.min_static_inliers; })},
        {"small_object_area_pct",
         Field<double>([](RunConfig& c) -> double& { return c.classifier.small_object_area_pct; })},
        {"motion_window_s", Field<double>([](RunConfig& c) -> double& { return c.classifier.motion_window_s; })}}},
      {"frontend",
       {{"flow_method",
         {[](const YAML::Node& n, RunConfig& c) { c.frontend.flow.method = ParseFlowMethod(n.as<std::string>()); },
          [](YAML::Emitter& e, const RunConfig& c) { e << ToString(c.frontend.flow.method); }}},
        {"fb_threshold_px", Field<double>([](RunConfig& c) -> double& { return c.frontend.flow.fb_threshold_px; })},
        {"lk_window_px", Field<int>([](RunConfig& c) -> int& { return c.frontend.flow.lk_window_px; })},
        {"lk_pyramid_levels", Field<int>([](RunConfig& c) -> int& { return c.frontend.flow.lk_pyramid_levels; })},
        {"warped_search_radius_px",
         Field<int>([](RunConfig& c) -> int& { return c.frontend.warped_search.radius_px; })},
        {"warped_search_min_ncc", Field<double>([](RunConfig& c) -> double& { return c.frontend.warped_search.min_ncc; })},
        {"warped_search_min_deformation",
         Field<double>([](RunConfig& c) -> double& { return c.frontend.warped_search.min_deformation; })},
        {"warped_search_max_flow_deformation",
         Field<double>([](RunConfig& c) -> double& { return c.frontend.warped_search.max_flow_deformation; })},
        {"static_cell_px", Field<int>([](RunConfig& c) -> int& { return c.frontend.static_grid.cell_px; })},
        {"static_per_cell", Field<int>([](RunConfig& c) -> int& { return c.frontend.static_grid.per_cell; })},
        {"fast_threshold", Field<int>([](RunConfig& c) -> int& { return c.frontend.static_grid.fast_threshold; })},
        {"object_cell_px", Field<int>([](RunConfig& c) -> int& { return c.frontend.object_grid.cell_px; })},
        {"object_lattice_step_px", Field<int>([](RunConfig& c) -> int& { return c.frontend.object_lattice_step_px; })},
        {"max_points_per_object", Field<int>([](RunConfig& c) -> int& { return c.frontend.max_points_per_object; })},
        {"min_points_per_object", Field<int>([](RunConfig& c) -> int& { return c.frontend.min_points_per_object; })},
        {"static_min_depth_m", Field<double>([](RunConfig& c) -> double& { return c.frontend.static_min_depth_m; })},
        {"static_max_depth_m", Field<double>([](RunConfig& c) -> double& { return c.frontend.static_max_depth_m; })},
        {"object_max_distance_m",
         Field<double>([](RunConfig& c) -> double& { return c.frontend.object_max_distance_m; })},
        {"min_mask_area_pct", Field<double>([](RunConfig& c) -> double& { return c.frontend.min_mask_area_pct; })},
        {"mask_border_px", Field<int>([](RunConfig& c) -> int& { return c.frontend.mask_border_px; })},
        {"mask_ids_tracked", Field<bool>([](RunConfig& c) -> bool& { return c.frontend.association.mask_ids_tracked; })},
        {"association_min_overlap",
         Field<double>([](RunConfig& c) -> double& { return c.frontend.association.min_overlap; })},
        {"pnp_reprojection_px", Field<double>([](RunConfig& c) -> double& { return c.frontend.pnp.reprojection_px; })},
        {"pnp_min_inliers", Field<int>([](RunConfig& c) -> int& { return c.frontend.pnp.min_inliers; })},
        {"odometry_gate_chi2", Field<double>([](RunConfig& c) -> double& { return c.frontend.odometry_gate_chi2; })},
        {"object_max_acceleration_mps2",
         Field<double>([](RunConfig& c) -> double& { return c.frontend.object_max_acceleration_mps2; })},
        {"object_ransac_threshold_m",
         Field<double>([](RunConfig& c) -> double& { return c.frontend.object_ransac.inlier_threshold_m; })}}},
      {"dataset",
       {{"depth_encoding", Field<std::string>([](RunConfig& c) -> std::string& { return c.dataset.depth_encoding; })},
        {"lidar_fill_radius_px", Field<int>([](RunConfig& c) -> int& { return c.dataset.lidar_fill_radius_px; })},
        {"stereo_num_disparities", Field<int>([](RunConfig& c) -> int& { return c.dataset.stereo.num_disparities; })},
        {"stereo_block_size", Field<int>([](RunConfig& c) -> int& { return c.dataset.stereo.block_size; })},
        {"stereo_lr_max_difference_px",
         Field<double>([](RunConfig& c) -> double& { return c.dataset.stereo.lr_max_difference_px; })},
        {"stereo_filter", Field<std::string>([](RunConfig& c) -> std::string& { return c.dataset.stereo.filter; })},
        {"stereo_wls_lambda", Field<double>([](RunConfig& c) -> double& { return c.dataset.stereo.wls_lambda; })},
        {"stereo_wls_sigma_color", Field<double>([](RunConfig& c) -> double& { return c.dataset.stereo.wls_sigma_color; })},
        {"stereo_wls_min_confidence",
         Field<double>([](RunConfig& c) -> double& { return c.dataset.stereo.wls_min_confidence; })},
        {"frame_rate_hz", Field<double>([](RunConfig& c) -> double& { return c.dataset.frame_rate_hz; })},
        {"override_times", Field<bool>([](RunConfig& c) -> bool& { return c.dataset.override_times; })},
        {"max_image_pixels", Field<int64_t>([](RunConfig& c) -> int64_t& { return c.dataset.max_image_pixels; })}}},
      {"masks",
       {{"source",
         {[](const YAML::Node& n, RunConfig& c) { c.masks.source = ParseMaskSource(n.as<std::string>()); },
          [](YAML::Emitter& e, const RunConfig& c) { e << ToString(c.masks.source); }}},
        {"lidar_from_depth", Field<bool>([](RunConfig& c) -> bool& { return c.masks.lidar_from_depth; })},
        {"lidar_depth_background_spread",
         Field<double>([](RunConfig& c) -> double& { return c.masks.lidar_depth_background_spread; })},
        {"lidar_max_range_m", Field<double>([](RunConfig& c) -> double& { return c.masks.lidar.segmentation.max_range_m; })},
        {"lidar_ground_distance_m",
         Field<double>([](RunConfig& c) -> double& { return c.masks.lidar.segmentation.ground_distance_m; })},
        {"lidar_ground_max_tilt_deg",
         Field<double>([](RunConfig& c) -> double& { return c.masks.lidar.segmentation.ground_max_tilt_deg; })},
        {"lidar_max_height_above_ground_m",
         Field<double>([](RunConfig& c) -> double& { return c.masks.lidar.segmentation.max_height_above_ground_m; })},
        {"lidar_cluster_tolerance_m",
         Field<double>([](RunConfig& c) -> double& { return c.masks.lidar.segmentation.cluster_tolerance_m; })},
        {"lidar_min_cluster_points",
         Field<int>([](RunConfig& c) -> int& { return c.masks.lidar.segmentation.min_cluster_points; })},
        {"lidar_min_object_height_m",
         Field<double>([](RunConfig& c) -> double& { return c.masks.lidar.segmentation.min_object_height_m; })},
        {"lidar_max_object_base_height_m",
         Field<double>([](RunConfig& c) -> double& { return c.masks.lidar.segmentation.max_object_base_height_m; })},
        {"lidar_max_object_length_m",
         Field<double>([](RunConfig& c) -> double& { return c.masks.lidar.segmentation.max_object_length_m; })},
        {"lidar_splat_half_width_px", Field<int>([](RunConfig& c) -> int& { return c.masks.lidar.splat_half_width_px; })},
        {"lidar_splat_half_height_px",
         Field<int>([](RunConfig& c) -> int& { return c.masks.lidar.splat_half_height_px; })},
        {"lidar_grow_px", Field<int>([](RunConfig& c) -> int& { return c.masks.lidar.grow_px; })},
        {"lidar_fov_top_deg", Field<double>([](RunConfig& c) -> double& { return c.masks.lidar.fov_top_deg; })},
        {"lidar_truncated_top_height_m",
         Field<double>([](RunConfig& c) -> double& { return c.masks.lidar.truncated_top_height_m; })}}},
  };
  return schema;
}
}  // namespace

RunConfig ParseRunConfig(const std::string& yaml_text, const std::string& source, const RunConfig& base) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(source + ": not valid YAML: " + e.what());
  }
  RunConfig config = base;
  if (root.IsNull()) return config;
  if (!root.IsMap()) throw std::invalid_argument(source + ": the top level must be a mapping of sections");
  const Schema& schema = GetSchema();
  std::set<std::string> seen;  // YAML readers disagree on repeated keys (first or last wins): refuse them
  for (const auto& section : root) {
    const std::string name = section.first.as<std::string>();
    if (!seen.insert(name).second) throw std::invalid_argument(source + ": section '" + name + "' appears twice");
    auto it = std::find_if(schema.begin(), schema.end(), [&](const auto& s) { return s.first == name; });
    if (it == schema.end()) throw std::invalid_argument(source + ": unknown section '" + name + "'");
    if (!section.second.IsMap()) throw std::invalid_argument(source + ": section '" + name + "' must be a mapping");
    for (const auto& entry : section.second) {
      const std::string key = entry.first.as<std::string>();
      if (!seen.insert(name + "." + key).second)
        throw std::invalid_argument(source + ": '" + name + "." + key + "' appears twice");
      auto field = std::find_if(it->second.begin(), it->second.end(), [&](const auto& f) { return f.first == key; });
      if (field == it->second.end()) throw std::invalid_argument(source + ": unknown key '" + name + "." + key + "'");
      try {
        field->second.read(entry.second, config);
      } catch (const YAML::Exception&) {
        throw std::invalid_argument(source + ": '" + name + "." + key + "' has the wrong type");
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(source + ": '" + name + "." + key + "': " + e.what());
      }
    }
  }
  try {
    config.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(source + ": " + e.what());
  }
  return config;
}

RunConfig LoadRunConfig(const std::string& path, const RunConfig& base) {
  // A configuration is a few kilobytes: read at most this much, so that a wrong path (a device, a log) is
  // refused at once rather than read until memory runs out.
  constexpr size_t kMaxConfigBytes = 4 << 20;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("cannot open configuration file " + path);
  std::string text(kMaxConfigBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<size_t>(in.gcount()));
  if (text.size() > kMaxConfigBytes)
    throw std::invalid_argument("configuration file " + path + " is over " + std::to_string(kMaxConfigBytes >> 20) +
                                " MB: not a configuration");
  return ParseRunConfig(text, path, base);
}

std::string RunConfigToYaml(const RunConfig& config) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  for (const auto& [section, fields] : GetSchema()) {
    out << YAML::Key << section << YAML::Value << YAML::BeginMap;
    for (const auto& [key, binding] : fields) {
      out << YAML::Key << key << YAML::Value;
      binding.write(out, config);
    }
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace dslam
