#pragma once
// The benchmarks' default scene: the built-in city rendered into a scratch folder (needs Xvfb or a
// display), for a bench run without a dataset.

#include <filesystem>
#include <iostream>
#include <string>

#include "app/render_scene_command.h"

namespace dslam::bench {

// `dir` when given; otherwise renders `frames` frames of the city into temp/`name` and returns that
// folder. Empty when rendering failed (the reason is on stderr).
inline std::string DatasetOrRenderedCity(const std::string& dir, int frames, const std::string& name) {
  if (!dir.empty()) return dir;
  RenderSceneOptions render;
  render.scenario = "city", render.frames = frames, render.quiet = true;
  render.out_dir = (std::filesystem::temp_directory_path() / name).string();
  if (RunRenderSceneCommand(render, std::cout, std::cerr) != 0) return "";
  return render.out_dir;
}

}  // namespace dslam::bench
