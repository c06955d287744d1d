#include "app/render_scene_command.h"

#include <chrono>
#include <cmath>
#include <exception>
#include <optional>

#include "data/kitti_dataset.h"
#include "data/odometry_file.h"
#include "render/exact_flow.h"
#include "render/headless_display.h"
#include "render/rgbd_renderer.h"
#include "render/sensor_noise.h"
#include "render/vdo_writer.h"
#include "simulation/scenarios.h"
#include "simulation/scene_builder.h"
#include "simulation/sensor_simulator.h"

namespace dslam {

int RunRenderSceneCommand(const RenderSceneOptions& options, std::ostream& out, std::ostream& err) {
  try {
    if (!(options.scale > 0.05 && options.scale <= 4.0)) throw std::invalid_argument("--scale must be in (0.05, 4]");
    if (options.frames < 0) throw std::invalid_argument("--frames must be >= 0");
    const SensorNoise noise{options.image_noise, options.depth_noise_m, options.depth_noise_per_m2};
    // NaN fails every comparison: the bounds are written so that it fails them.
    if (!(noise.image_sigma >= 0.0 && noise.image_sigma <= 255.0))
      throw std::invalid_argument("--image-noise must be in [0, 255] grey levels");
    if (!(noise.depth_sigma_m >= 0.0 && noise.depth_sigma_m <= 10.0))
      throw std::invalid_argument("--depth-noise must be in [0, 10] m");
    if (!(noise.depth_sigma_per_m2 >= 0.0 && noise.depth_sigma_per_m2 <= 1.0))
      throw std::invalid_argument("--depth-noise-per-m2 must be in [0, 1] m per m^2");
    if (options.kitti_dir.empty() == options.scenario.empty())
      throw std::invalid_argument("give either --kitti DIR --seq SSSS or --scenario NAME");
    Scene scene;
    CameraIntrinsics camera;
    double baseline_m = kKittiStereoBaselineM;
    std::string what;
    if (!options.kitti_dir.empty()) {
      const KittiGroundTruthSequence gt = LoadKittiGroundTruth(options.kitti_dir, options.sequence);
      scene = SceneFromKitti(gt);
      if (gt.calibration) {
        camera.fx = gt.calibration->fx(), camera.fy = gt.calibration->fy();
        camera.cx = gt.calibration->cx(), camera.cy = gt.calibration->cy();
        // The sequence's own stereo baseline, between its colour cameras (P2, P3), when it gives one.
        const double b = (gt.calibration->P[2](0, 3) - gt.calibration->P[3](0, 3)) / gt.calibration->fx();
        if (b > 0.0 && std::isfinite(b)) baseline_m = b;
      }
      what = "KITTI " + options.sequence;
    } else {
      ScenarioOptions scenario;
      scenario.num_frames = options.frames;
      scenario.seed = options.seed;
      scene = SceneFromSequence(MakeScenario(options.scenario, scenario));
      if (scene.objects.empty())
        throw std::invalid_argument("scenario '" + options.scenario + "' has no box objects to render (try city)");
      what = "scenario " + options.scenario;
    }
    camera.width = static_cast<int>(std::lround(camera.width * options.scale));
    camera.height = static_cast<int>(std::lround(camera.height * options.scale));
    camera.fx *= options.scale, camera.fy *= options.scale;
    camera.cx = (camera.cx + 0.5) * options.scale - 0.5, camera.cy = (camera.cy + 0.5) * options.scale - 0.5;

    std::string error;
    const auto display = HeadlessDisplay::Acquire(&error);
    if (!display) {
      err << "dslam render-scene: error: " << error << std::endl;
      return 3;
    }
    RgbdRenderer renderer(camera, scene.static_quads);
    VdoWriter writer(options.out_dir, scene, camera, options.stereo ? baseline_m : 0.0);
    const SE3 T_left_right(Eigen::Quaterniond::Identity(), Vec3(baseline_m, 0.0, 0.0));
    std::optional<RgbdFrame> previous;  // for the exact flow from it to the frame just rendered
    const int frames = options.frames > 0 ? std::min<int>(options.frames, scene.T_world_camera.size())
                                          : static_cast<int>(scene.T_world_camera.size());
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < frames; ++k) {
      std::vector<RenderBox> boxes;
      for (const auto& o : scene.objects) {
        const auto pose = o.L_world_object.find(k);
        if (pose == o.L_world_object.end()) continue;
        boxes.push_back({o.object_id, pose->second, o.l, o.w, o.h, o.texture_seed});
      }
      RgbdFrame frame = renderer.render(scene.T_world_camera[k], boxes);
      std::optional<RgbdFrame> right;
      if (options.stereo) right = renderer.render(scene.T_world_camera[k] * T_left_right, boxes);
      // The flow is exact: it comes from the noiseless depth, before the noise is added.
      if (options.exact_flow && previous) writer.writeFlow(k - 1, ExactFlow(scene, k - 1, *previous, frame, camera));
      if (options.exact_flow) previous = frame;
      if (noise.any()) {
        AddSensorNoise(noise, options.seed * 1000003ULL + static_cast<uint64_t>(k), &frame);
        if (right) AddSensorNoise(noise, options.seed * 1000003ULL + 500009ULL + static_cast<uint64_t>(k), &*right);
      }
      writer.write(k, frame, right ? &*right : nullptr);
      if (!options.quiet && ((k + 1) % std::max(1, frames / 10) == 0 || k + 1 == frames)) {
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        out << "  frame " << k + 1 << "/" << frames << ", " << (k + 1) / s << " frames/s" << std::endl;
      }
    }
    // A vehicle's odometry beside the images: the true increments with the simulator's odometry noise (docs/design.md §10), seeded.
    std::mt19937_64 rng(options.seed * 2862933555777941757ULL + 3037000493ULL);
    std::map<int, OdometryMeasurement> odometry;
    for (int k = 1; k < frames; ++k)
      odometry[k] = NoisyOdometry(scene.T_world_camera[k - 1].inverse() * scene.T_world_camera[k], SimNoise{}, rng);
    WriteOdometryFile(options.out_dir + "/odometry.txt", odometry);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out << "Rendered " << frames << " frames of " << what << " at " << camera.width << "x"
        << camera.height << " in " << seconds << " s (" << frames / seconds << " frames/s, with writing) to "
        << options.out_dir << std::endl;
    return 0;
  } catch (const std::exception& e) {
    err << "dslam render-scene: error: " << e.what() << std::endl;
    return 2;
  }
}

}  // namespace dslam
