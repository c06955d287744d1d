#pragma once
// A scene of the built-in city rendered for a test (colour, depth, masks, odometry, ground truth). Rendering
// takes a few seconds, so a scene is made once per process and name; under ctest (which sets
// DSLAM_TEST_RENDER_CACHE, emptied at the start of every ctest run) once per run, shared by every test process
// that asks for the same scene. Tests only read these directories.

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>

#include "app/render_scene_command.h"
#include "support/no_display.h"
#include "support/temp_paths.h"

namespace dslam::test {

inline void RenderCity(const std::string& dir, int frames, uint64_t seed, bool stereo_and_exact_flow, double scale) {
  ScopedNoDisplay no_display;  // through our own Xvfb, as CI renders
  RenderSceneOptions render;
  render.scenario = "city", render.frames = frames, render.seed = seed, render.out_dir = dir, render.quiet = true;
  render.stereo = render.exact_flow = stereo_and_exact_flow;
  render.scale = scale;
  std::ostringstream out, err;
  if (RunRenderSceneCommand(render, out, err) != 0) throw std::runtime_error("rendering the city failed: " + err.str());
}

// Holds an exclusive lock on `path` (created when missing) for its lifetime.
class FileLock {
 public:
  explicit FileLock(const std::string& path) : fd_(::open(path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644)) {
    if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0) throw std::runtime_error("cannot lock " + path);
  }
  ~FileLock() { ::close(fd_); }  // closing releases the lock
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

// The scene rendered once into the shared directory `cache`: the first caller renders, the others (other
// processes, or threads: flock locks belong to each open) wait on the lock. The scene is renamed into place only
// when whole, so a process killed mid-render leaves no half scene behind. `key` names the scene and its
// parameters.
inline std::string RenderedCityIn(const std::string& cache, const std::string& key, int frames, uint64_t seed,
                                  bool stereo_and_exact_flow, double scale) {
  const std::string dir = cache + "/" + key;
  std::filesystem::create_directories(cache);
  const FileLock lock(dir + ".lock");
  if (!std::filesystem::exists(dir + "/odometry.txt")) {
    const std::string partial = dir + ".partial." + std::to_string(::getpid());
    std::filesystem::remove_all(partial);
    RenderCity(partial, frames, seed, stereo_and_exact_flow, scale);
    std::filesystem::remove_all(dir);
    std::filesystem::rename(partial, dir);
  }
  return dir;
}

// `stereo_and_exact_flow`: also the right camera (image_1/) and the exact flow (flow/), for the study.
// `name` names the scene within this process. In the shared cache a scene is named by its parameters alone, as
// rendering is deterministic: tests that ask for the same scene under different names share it.
inline std::string RenderedCity(const std::string& name, int frames, uint64_t seed = 1,
                                bool stereo_and_exact_flow = false, double scale = 1.0) {
  const char* cache = std::getenv("DSLAM_TEST_RENDER_CACHE");
  if (cache && *cache) {
    std::ostringstream key;
    key << "city_f" << frames << "_s" << seed << (stereo_and_exact_flow ? "_stereo" : "") << "_x" << scale;
    return RenderedCityIn(cache, key.str(), frames, seed, stereo_and_exact_flow, scale);
  }
  const std::string dir = TempPath(name);
  if (!std::filesystem::exists(dir + "/odometry.txt")) RenderCity(dir, frames, seed, stereo_and_exact_flow, scale);
  return dir;
}

}  // namespace dslam::test
