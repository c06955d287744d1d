// `dslam run` end to end on a short rendered city scene, and its answers to bad input.
#include "app/run_command.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/figures_command.h"
#include "app/render_scene_command.h"
#include "support/child_process.h"
#include "support/no_display.h"
#include "support/rendered_city.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

// 25 frames of the built-in city, rendered once for the tests of this file.
const std::string& CityDataset() {
  static const std::string dir = test::RenderedCity("run_city", 25);
  return dir;
}

TEST(RunCommand, RunsTheImagePipelineAndWritesResultsFiguresAndAFrameLog) {
  test::ScopedNoDisplay no_display;
  RunCommandOptions options;
  options.dataset_dir = CityDataset();
  options.out_dir = test::TempPath("run_out");
  std::ostringstream out, err;
  ASSERT_EQ(RunRunCommand(options, out, err), 0) << err.str();
  const std::string text = out.str();
  EXPECT_NE(text.find("(vdo): 25 frames 1242x375, masks yes, odometry yes, ground truth yes"), std::string::npos) << text;
  EXPECT_NE(text.find("front-end: frame 25/25"), std::string::npos);
  EXPECT_NE(text.find("frames/s"), std::string::npos);
  for (const char* f : {"metrics.json", "camera_ours.tum", "camera_gt.kitti", "object_speeds.csv", "objects.csv",
                        "frontend.csv", "trajectory.png", "speeds.png", "report.html"})
    EXPECT_TRUE(fs::exists(options.out_dir + "/" + f)) << f;

  std::ifstream in(options.out_dir + "/metrics.json");
  const nlohmann::json metrics = nlohmann::json::parse(in);
  const auto& ours = metrics["methods"]["ours"];
  EXPECT_LT(ours["rte_pct"].get<double>(), 2.0);
  EXPECT_LT(ours["omse_pct"].get<double>(), 10.0);
  EXPECT_GE(ours["object_coverage"].get<double>(), 0.8);
  EXPECT_EQ(metrics["run"]["flow_method"], "lk");
  EXPECT_GT(metrics["run"]["frontend"]["mean_static_points"].get<double>(), 200.0);
  EXPECT_TRUE(metrics["methods"].contains("static_only"));
  EXPECT_TRUE(metrics["methods"].contains("slam_mot"));
  // Ours ran online: the latency of each stage, over every frame.
  const auto& latency = metrics["run"]["latency_ms"];
  for (const char* stage : {"input", "frontend", "backend", "total"}) EXPECT_EQ(latency[stage]["frames"], 25) << stage;
  EXPECT_GE(latency["total"]["median_ms"].get<double>(), latency["frontend"]["median_ms"].get<double>());
  EXPECT_NE(text.find("Latency per stage, ms (median/p99): input "), std::string::npos) << text;
}

TEST(RunCommand, DenseFlowAndOverlapAssociationAlsoFollowTheCars) {
  RunCommandOptions options;
  options.dataset_dir = CityDataset();
  options.out_dir = test::TempPath("run_dis");
  options.flow = "dis";
  options.methods = {"ours"};
  options.no_figures = true;
  options.config_path = test::TempPath("overlap.yaml");
  std::ofstream(*options.config_path) << "frontend:\n  mask_ids_tracked: false\n";
  std::ostringstream out, err;
  ASSERT_EQ(RunRunCommand(options, out, err), 0) << err.str();
  std::ifstream in(options.out_dir + "/metrics.json");
  const nlohmann::json metrics = nlohmann::json::parse(in);
  EXPECT_EQ(metrics["run"]["flow_method"], "dis");
  EXPECT_FALSE(metrics["methods"].contains("slam_mot"));
  // Object ids are the front-end's own now, so only the camera is compared with the ground truth.
  EXPECT_LT(metrics["methods"]["ours"]["rte_pct"].get<double>(), 2.0);
  std::ifstream objects(options.out_dir + "/objects.csv");
  std::string header, line;
  std::getline(objects, header);
  int rows = 0;
  while (std::getline(objects, line)) ++rows;
  EXPECT_GE(rows, 3);  // the city's cars in view
}

TEST(RunCommand, WithoutGroundTruthEveryFigureThatNeedsNoneIsDrawnAndTheExitIs0) {
  test::ScopedNoDisplay no_display;
  const std::string data = test::TempPath("run_city_no_gt");
  fs::remove_all(data);
  fs::create_directories(data);
  for (const char* entry : {"calib.txt", "image_0", "depth", "mask", "odometry.txt", "times.txt"})
    fs::copy(CityDataset() + "/" + entry, data + "/" + entry, fs::copy_options::recursive);
  RunCommandOptions options;
  options.dataset_dir = data;
  options.frames = 10;
  options.out_dir = test::TempPath("run_no_gt_out");
  std::ostringstream out, err;
  ASSERT_EQ(RunRunCommand(options, out, err), 0) << err.str() << out.str();
  EXPECT_NE(out.str().find("No ground truth"), std::string::npos) << out.str();
  for (const char* f : {"trajectory.png", "speeds.png", "map.png", "report.html"})
    EXPECT_TRUE(fs::exists(options.out_dir + "/" + f)) << f;
  EXPECT_FALSE(fs::exists(options.out_dir + "/errors.png"));
  // What serve leaves (no ground-truth centroids, no per-object table) is drawn too.
  fs::remove(options.out_dir + "/object_centroids_gt.csv");
  fs::remove(options.out_dir + "/objects.csv");
  fs::remove(options.out_dir + "/trajectory.png");
  std::ostringstream out2, err2;
  EXPECT_EQ(RunFiguresCommand(options.out_dir, FigureOptions{}, out2, err2), 0) << err2.str();
  EXPECT_TRUE(fs::exists(options.out_dir + "/trajectory.png"));
}

TEST(RunCommand, ARunWithoutOursDrawsTheFiguresOfTheMethodItRan) {
  // `run --methods static_only` used to fail its figures (exit 2) for want of camera_ours.tum.
  test::ScopedNoDisplay no_display;
  for (const std::string method : {"static_only", "slam_mot"}) {
    RunCommandOptions options;
    options.dataset_dir = CityDataset();
    options.frames = 6;
    options.methods = {method};
    options.out_dir = test::TempPath("run_only_" + method);
    std::ostringstream out, err;
    ASSERT_EQ(RunRunCommand(options, out, err), 0) << method << ": " << err.str() << out.str();
    for (const char* f : {"trajectory.png", "errors.png", "map.png", "report.html"})
      EXPECT_TRUE(fs::exists(options.out_dir + "/" + f)) << method << " " << f;
    // Speeds need object estimates: SLAM+MOT has them, static-only not.
    EXPECT_EQ(fs::exists(options.out_dir + "/speeds.png"), method == "slam_mot") << method;
    EXPECT_NE(test::ReadFile(options.out_dir + "/report.html").find(method), std::string::npos) << method;
  }
}

TEST(RunCommand, BadInputGivesOneLineAndExitStatus2) {
  const std::string dir = test::TempDir("run_bad");
  fs::create_directories(dir + "/image_0");
  RunCommandOptions options;
  options.dataset_dir = dir;
  options.out_dir = test::TempPath("run_bad_out");
  std::ostringstream out, err;
  EXPECT_EQ(RunRunCommand(options, out, err), 2);
  EXPECT_NE(err.str().find("dslam run: error: no .png images in " + dir + "/image_0"), std::string::npos) << err.str();

  options.dataset_dir = CityDataset();
  options.flow = "precomputed";  // the rendered city has no flow/ folder
  err.str("");
  EXPECT_EQ(RunRunCommand(options, out, err), 2);
  EXPECT_NE(err.str().find("has no flow/ folder"), std::string::npos) << err.str();

  // An --out that cannot be written is found at the start, not after the whole run.
  const std::string a_file = test::TempPath("run_out_is_a_file");
  std::ofstream(a_file) << "x";
  options.out_dir = a_file + "/results";
  err.str("");
  EXPECT_EQ(RunRunCommand(options, out, err), 2);
  EXPECT_NE(err.str().find("cannot create the output folder " + a_file + "/results"), std::string::npos) << err.str();
  EXPECT_EQ(out.str().find("front-end: frame"), std::string::npos);  // nothing was computed
  options.out_dir = test::TempPath("run_bad_out");

  // A flow method other than precomputed never reads flow/*.flo, so a corrupt one does not stop it.
  const std::string with_flow = test::TempDir("run_corrupt_flow");
  fs::copy(CityDataset(), with_flow, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  fs::create_directories(with_flow + "/flow");
  for (int k = 0; k < 25; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "/flow/%06d.flo", k);
    std::ofstream(with_flow + name) << "not a flow file";
  }
  options.dataset_dir = with_flow;
  options.flow = "lk";
  options.frames = 3;
  options.no_figures = true;
  err.str("");
  EXPECT_EQ(RunRunCommand(options, out, err), 0) << err.str();
  options.flow = "precomputed";
  EXPECT_EQ(RunRunCommand(options, out, err), 2);
  EXPECT_NE(err.str().find(".flo"), std::string::npos) << err.str();

  // Render noise out of range, or NaN, is an error rather than black images or no noise.
  for (double bad : {1e30, std::nan(""), -1.0}) {
    RenderSceneOptions render;
    render.scenario = "city";
    render.frames = 2;
    render.image_noise = bad;
    render.out_dir = test::TempPath("render_bad_noise");
    std::ostringstream rout, rerr;
    EXPECT_EQ(RunRenderSceneCommand(render, rout, rerr), 2) << bad;
    EXPECT_NE(rerr.str().find("--image-noise must be in [0, 255]"), std::string::npos) << rerr.str();
  }

  const std::string bin = DSLAM_BINARY;
  for (const char* args : {"run", "run --dataset /nonexistent", "run --dataset . --flow farneback",
                           "run --dataset . --methods nobody"}) {
    const int status = std::system((bin + " " + args + " > /dev/null 2>&1").c_str());
    ASSERT_TRUE(WIFEXITED(status)) << args;
    EXPECT_NE(WEXITSTATUS(status), 0) << args;
  }
  EXPECT_EQ(std::system((bin + " run --help > /dev/null").c_str()), 0);
}

// A frame that cannot be read mid-run ends the run there, keeping every frame before it estimated and written
// whole; the error names the file and the exit status is 2.
TEST(RunCommand, AFrameThatCannotBeReadEndsTheRunAndKeepsTheFramesBeforeIt) {
  const std::string dir = test::TempDir("run_corrupt_frame");
  fs::copy(CityDataset(), dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  const std::string corrupt = dir + "/image_0/000012.png";
  ASSERT_TRUE(fs::exists(corrupt));
  std::ofstream(corrupt, std::ios::trunc) << "not a png";
  RunCommandOptions options;
  options.dataset_dir = dir;
  options.out_dir = test::TempPath("run_corrupt_frame_out");
  options.no_figures = true;
  std::ostringstream out, err;
  EXPECT_EQ(RunRunCommand(options, out, err), 2);
  EXPECT_NE(err.str().find("000012.png"), std::string::npos) << err.str();
  EXPECT_NE(err.str().find("the 12 frames before it were estimated and written"), std::string::npos) << err.str();
  std::ifstream in(options.out_dir + "/metrics.json");
  const nlohmann::json metrics = nlohmann::json::parse(in);
  EXPECT_EQ(metrics["run"]["frames"], 12);
  EXPECT_NE(metrics["run"]["stopped_by"].get<std::string>().find("000012.png"), std::string::npos);
  EXPECT_LT(metrics["methods"]["ours"]["rte_pct"].get<double>(), 2.0);  // evaluated over the frames run
  for (const char* name : {"camera_ours.tum", "camera_static_only.tum", "camera_slam_mot.tum", "camera_gt.tum"}) {
    std::ifstream tum(options.out_dir + "/" + name);
    int lines = 0;
    for (std::string line; std::getline(tum, line);) lines += !line.empty() && line[0] != '#';
    EXPECT_EQ(lines, 12) << name;  // every frame before the bad one, its window flushed
  }
  std::ifstream centroids(options.out_dir + "/object_centroids_gt.csv");
  std::string row;
  std::getline(centroids, row);  // header
  int rows = 0;
  for (; std::getline(centroids, row); ++rows) EXPECT_LT(std::stoi(row), 12) << row;  // only the frames run
  EXPECT_GT(rows, 0);
}

}  // namespace
}  // namespace dslam
