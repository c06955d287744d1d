// The command line's own errors: exit status 2 (README, "Exit status") with a line that names the problem.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "support/child_process.h"
#include "support/rendered_city.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
using namespace std::chrono_literals;

struct Outcome {
  int status;
  std::string output;
};

Outcome Dslam(const std::vector<std::string>& args) {
  const std::string log = test::TempPath("cli.log");
  test::Process p(args, log);
  const int status = p.wait(60s);
  return {status, test::ReadFile(log)};
}

std::string SharedLibrariesOf(const std::string& binary) {
  FILE* pipe = popen(("ldd " + binary + " 2>&1").c_str(), "r");
  if (!pipe) return {};
  std::string libraries;
  char buffer[4096];
  while (fgets(buffer, sizeof(buffer), pipe)) libraries += buffer;
  pclose(pipe);
  return libraries;
}

// PCL, OpenCV's image codecs (and through them GDAL) and its contrib filters are loaded only by the commands
// that use them (data/runtime_module.h): together they took ~0.25 s of every process's start-up. VTK, MPI and
// Fast DDS (~50 ms) are in dslam-full, which dslam hands the commands that need them (app/full_binary.h).
TEST(Cli, DslamStartsWithoutTheLibrariesOnlySomeCommandsNeed) {
  const std::string libraries = SharedLibrariesOf(DSLAM_BINARY);
  ASSERT_NE(libraries.find("libopencv_core"), std::string::npos) << libraries;  // ldd did list them
  for (const char* optional :
       {"libpcl_", "libgdal", "libopencv_imgcodecs", "libopencv_ximgproc", "libvtk", "libmpi", "libfastrtps"})
    EXPECT_EQ(libraries.find(optional), std::string::npos) << optional << " is linked into dslam";
  const std::string full = SharedLibrariesOf(DSLAM_BINARY_DIR "/dslam-full");
  for (const char* needed : {"libvtkRenderingCore", "libfastrtps"})
    EXPECT_NE(full.find(needed), std::string::npos) << needed << " is not linked into dslam-full: " << full;
  // The commands of dslam-full, through dslam: the help of each, its usage line naming what the user typed.
  for (const char* command : {"serve", "publish", "listen", "figures", "render-scene", "study"}) {
    const Outcome o = Dslam({command, "--help"});
    EXPECT_EQ(o.status, 0) << command << ": " << o.output;
    EXPECT_NE(o.output.find(std::string("dslam ") + command + " [OPTIONS]"), std::string::npos) << o.output;
  }
}

TEST(Cli, BadCommandsAndOptionsExitWithStatus2AndSaySo) {
  Outcome o = Dslam({"frobnicate"});
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.output.find("unknown command 'frobnicate'"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("run"), std::string::npos) << o.output;  // lists the commands

  o = Dslam({"run", "--dataset", DSLAM_SOURCE_DIR, "--bogus"});
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("--bogus"), std::string::npos) << o.output;

  const std::string calib = std::string(DSLAM_SOURCE_DIR) + "/README.md";  // exists; never read here
  for (const char* domain : {"300", "-1"}) {
    o = Dslam({"serve", "--calib", calib, "--domain", domain});
    EXPECT_EQ(o.status, 2) << domain << ": " << o.output;
    EXPECT_NE(o.output.find("--domain"), std::string::npos) << o.output;
  }
  // Every option's range is checked when the command line is read: out-of-range values are bad input (2),
  // never a run that does something else (publish --frames -3 published everything, serve --max-run -5
  // never stopped, serve --rate 0 and --out FILE ended in status 4).
  const std::string src = DSLAM_SOURCE_DIR, a_file = src + "/README.md";
  const std::vector<std::pair<std::vector<std::string>, std::string>> table = {
      {{"serve", "--calib", calib, "--rate", "0"}, "--rate"},
      {{"serve", "--calib", calib, "--rate", "5000"}, "--rate"},
      {{"serve", "--calib", calib, "--max-run", "-5"}, "--max-run"},
      {{"serve", "--calib", calib, "--status-every", "-1"}, "--status-every"},
      {{"serve", "--calib", calib, "--out", a_file}, "is a file, not a folder"},
      {{"serve", "--calib", calib, "--max-pending", "0"}, "--max-pending"},
      {{"serve", "--calib", calib, "--fleet-share", "0/2"}, "--fleet-share needs the fleet's --vehicle list"},
      {{"serve", "--calib", calib, "--vehicle", "a", "--fleet-share", "2/2"}, "--fleet-share '2/2'"},
      {{"serve", "--calib", calib, "--vehicle", "a", "--fleet-share", "1/2"}, "leaves this host no vehicle"},
      {{"serve", "--calib", calib, "--vehicle", "a", "--vehicle", "a", "--fleet-share", "0/1"}, "named twice"},
      {{"publish", "--dataset", src, "--frames", "-3"}, "--frames"},
      {{"publish", "--dataset", src, "--start-frame", "-1"}, "--start-frame"},
      {{"publish", "--dataset", src, "--rate", "0"}, "--rate"},
      {{"publish", "--dataset", src, "--wait", "-2"}, "--wait"},
      {{"run", "--dataset", src, "--frames", "-1"}, "--frames"},
      {{"run", "--dataset", src, "--sigma", "0"}, "--sigma"},
      {{"run", "--dataset", src, "--out", a_file}, "is a file, not a folder"},
      {{"sim", "--frames", "200000"}, "--frames"},
      {{"sim", "--sigma", "-0.1"}, "--sigma"},
      {{"sim", "--out", a_file}, "is a file, not a folder"},
      {{"kitti-replay", "--data", src, "--seq", "0000", "--sigma", "0"}, "--sigma"},
      {{"render-scene", "--scenario", "city", "--scale", "0"}, "--scale"},
      {{"render-scene", "--scenario", "city", "--image-noise", "300"}, "--image-noise"},
      {{"render-scene", "--scenario", "city", "--frames", "-4"}, "--frames"},
      {{"figures", src, "--width", "10"}, "--width"},
      {{"lidar-check", "--dataset", src, "--frames", "-1"}, "--frames"},
      {{"study", "--dataset", src, "--frames", "-1"}, "--frames"},
  };
  for (const auto& [args, named] : table) {
    o = Dslam(args);
    std::string line;
    for (const std::string& a : args) line += a + " ";
    EXPECT_EQ(o.status, 2) << line << ": " << o.output;
    EXPECT_NE(o.output.find(named), std::string::npos) << line << ": " << o.output;
  }

  o = Dslam({"sim", "--help"});
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("--scenario"), std::string::npos);
}

TEST(Cli, ACutOrOversizedImageIsOneLineOfOursNamingTheFile) {
  // A copy of the 12-frame city (rendered once per ctest run) with frame 2's colour image cut short.
  const std::string city = test::RenderedCity("cli_city_12", 12, 1);
  const std::string dir = test::TempPath("cli_cut_png");
  std::filesystem::copy(city, dir, std::filesystem::copy_options::recursive);
  const std::string image = dir + "/image_0/000002.png";
  std::filesystem::resize_file(image, std::filesystem::file_size(image) / 2);
  Outcome o = Dslam({"run", "--dataset", dir, "--frames", "4", "--methods", "ours", "--no-figures", "--quiet",
                     "--out", test::TempPath("cli_cut_png_out")});
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_EQ(o.output, "dslam run: error: cannot read image " + image + ": " +
                          o.output.substr(o.output.find("PNG cut off")));  // nothing before ours
  EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << o.output;
  EXPECT_EQ(o.output.find("libpng"), std::string::npos) << o.output;

  // An image bigger than dataset.max_image_pixels is refused from its header.
  const std::string config = test::TempPath("cli_small_images.yaml");
  std::ofstream(config) << "dataset: {max_image_pixels: 1000}\n";
  o = Dslam({"run", "--dataset", city, "--frames", "2", "--methods", "ours", "--no-figures", "--quiet", "--config",
             config, "--out", test::TempPath("cli_small_images_out")});
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("more than the 1000 allowed (dataset.max_image_pixels)"), std::string::npos) << o.output;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace dslam
