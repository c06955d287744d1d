#pragma once
// A scene of the built-in city rendered for a test (colour, depth, masks, odometry, ground truth), made
// once per process and name: rendering takes a few seconds.

#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>

#include "app/render_scene_command.h"
#include "support/no_display.h"
#include "support/temp_paths.h"

namespace dslam::test {

// `stereo_and_exact_flow`: also the right camera (image_1/) and the exact flow (flow/), for the study.
inline std::string RenderedCity(const std::string& name, int frames, uint64_t seed = 1,
                                bool stereo_and_exact_flow = false, double scale = 1.0) {
  const std::string dir = TempPath(name);
  if (std::filesystem::exists(dir + "/odometry.txt")) return dir;
  ScopedNoDisplay no_display;  // through our own Xvfb, as CI renders
  RenderSceneOptions render;
  render.scenario = "city", render.frames = frames, render.seed = seed, render.out_dir = dir, render.quiet = true;
  render.stereo = render.exact_flow = stereo_and_exact_flow;
  render.scale = scale;
  std::ostringstream out, err;
  if (RunRenderSceneCommand(render, out, err) != 0) throw std::runtime_error("rendering the city failed: " + err.str());
  return dir;
}

}  // namespace dslam::test
