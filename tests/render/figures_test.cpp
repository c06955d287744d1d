#include "render/figures.h"

#include <gtest/gtest.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <csignal>
#include <set>
#include <sstream>
#include <thread>

#include "app/figures_command.h"
#include "output/result_reader.h"
#include "output/run_report.h"
#include "pipeline/run_sequence.h"
#include "render/headless_display.h"
#include "simulation/scenarios.h"
#include "support/child_process.h"
#include "support/no_display.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

namespace fs = std::filesystem;

// A small `city` run written with the regular writers: real result files with known trajectories.
std::string MakeResults(const std::string& name, bool sliding_window = false) {
  const std::string dir = test::TempDir(name);
  ScenarioOptions opt;
  opt.num_frames = 40;
  const Sequence seq = MakeScenario("city", opt);
  RunConfig config;
  config.backend.default_mode = MotionMode::kSmoothed;
  if (sliding_window) config.backend.schedule = {ScheduleKind::kSlidingWindow, 10};  // speeds with their sigma
  WriteRunOutputs(dir, seq, RunSequence(seq, config), {{"command", "sim"}, {"scenario", "city"}});
  return dir;
}

struct Png {
  int width = 0, height = 0;
  vtkNew<vtkImageData> image;
  std::array<int, 3> at(int x, int y) const {
    auto* p = static_cast<unsigned char*>(const_cast<vtkImageData*>(image.Get())->GetScalarPointer(x, y, 0));
    return {p[0], p[1], p[2]};
  }
};

std::unique_ptr<Png> Load(const std::string& path) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  auto png = std::make_unique<Png>();
  png->image->DeepCopy(reader->GetOutput());
  int dims[3];
  png->image->GetDimensions(dims);
  png->width = dims[0];
  png->height = dims[1];
  return png;
}

double NonWhiteFraction(const Png& png) {
  long count = 0;
  for (int y = 0; y < png.height; ++y)
    for (int x = 0; x < png.width; ++x) {
      const auto c = png.at(x, y);
      count += (c[0] + c[1] + c[2]) < 720;
    }
  return static_cast<double>(count) / (static_cast<double>(png.width) * png.height);
}

bool ColourNear(const Png& png, int x, int y, const std::array<unsigned char, 3>& colour, int radius = 3) {
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int px = x + dx, py = y + dy;
      if (px < 0 || py < 0 || px >= png.width || py >= png.height) continue;
      const auto c = png.at(px, py);
      if (std::abs(c[0] - colour[0]) < 40 && std::abs(c[1] - colour[1]) < 40 && std::abs(c[2] - colour[2]) < 40)
        return true;
    }
  return false;
}

class Figures : public ::testing::Test {
 protected:
  test::ScopedNoDisplay headless_;  // the project's own display handling, as on a headless server
};

TEST_F(Figures, TrajectoryShowsGroundTruthAndEstimateWhereTheyMustPass) {
  const std::string dir = MakeResults("traj");
  const RunResults results = ReadRunResults(dir);
  std::string error;
  PlotArea area;
  {
    auto display = HeadlessDisplay::Acquire(&error);
    ASSERT_TRUE(display) << error;
    EXPECT_TRUE(display->ownsServer());
    area = DrawTrajectoryFigure(results, dir + "/trajectory.png", FigureOptions{});
  }
  EXPECT_EQ(std::getenv("DISPLAY"), nullptr);  // our Xvfb is gone again
  const auto png = Load(dir + "/trajectory.png");
  EXPECT_EQ(png->width, 1600);
  EXPECT_EQ(png->height, 1000);
  EXPECT_GT(NonWhiteFraction(*png), 0.01);
  // Equal axes: one metre is as many pixels across as up.
  EXPECT_NEAR((area.x1 - area.x0) / (area.xmax - area.xmin), (area.y1 - area.y0) / (area.ymax - area.ymin), 1e-6);
  auto pixel = [&](const Vec3& p) {
    return std::pair<int, int>(
        static_cast<int>(std::lround(area.x0 + (p.x() - area.xmin) / (area.xmax - area.xmin) * (area.x1 - area.x0))),
        static_cast<int>(std::lround(area.y0 + (p.z() - area.ymin) / (area.ymax - area.ymin) * (area.y1 - area.y0))));
  };
  int gt_hits = 0, est_hits = 0;
  for (size_t k = 5; k < results.camera_gt.size(); k += 5) {
    const auto [gx, gy] = pixel(results.camera_gt[k].translation());
    const auto [ex, ey] = pixel(results.camera_est[k].translation());
    gt_hits += ColourNear(*png, gx, gy, kGroundTruthColour);
    est_hits += ColourNear(*png, ex, ey, kEstimateColour);
  }
  EXPECT_GE(gt_hits, 6);
  EXPECT_GE(est_hits, 6);
  // Away from every trajectory (a corner of the plot area) the background is white.
  EXPECT_FALSE(ColourNear(*png, area.x1 - 5, area.y0 + 5, kEstimateColour, 2));
  fs::remove_all(dir);
}

TEST_F(Figures, CommandDrawsEveryFigureAndTheReportDeterministically) {
  const std::string dir = MakeResults("all");
  std::ostringstream out, err;
  ASSERT_EQ(RunFiguresCommand(dir, FigureOptions{}, out, err), 0) << err.str();
  for (const char* f : {"trajectory.png", "speeds.png", "errors.png", "map.png"}) {
    const auto png = Load(dir + "/" + f);
    EXPECT_EQ(png->width, 1600) << f;
    EXPECT_EQ(png->height, 1000) << f;
    EXPECT_GT(NonWhiteFraction(*png), 0.005) << f;
  }
  std::ifstream html(dir + "/report.html");
  const std::string page((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
  for (const char* needle : {"<table>", "Object motion translation error (OMTE)", "SLAM+MOT", "src=\"trajectory.png\"",
                             "src=\"map.png\""})
    EXPECT_NE(page.find(needle), std::string::npos) << needle;
  EXPECT_EQ(page.find("http"), std::string::npos);  // opens from disk, nothing fetched

  auto bytes = [](const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string first = bytes(dir + "/trajectory.png"), first_map = bytes(dir + "/map.png");
  ASSERT_EQ(RunFiguresCommand(dir, FigureOptions{}, out, err), 0) << err.str();
  EXPECT_EQ(bytes(dir + "/trajectory.png"), first);
  EXPECT_EQ(bytes(dir + "/map.png"), first_map);

  FigureOptions print;
  print.scale = 2.0;
  ASSERT_EQ(RunFiguresCommand(dir, print, out, err), 0) << err.str();
  EXPECT_EQ(Load(dir + "/speeds.png")->width, 3200);

  // Frames a run drew its objects on (dslam run on images) join the report, with what they show; a half-written
  // one does not.
  std::ofstream(dir + "/frame_000012.png") << "png";
  std::ofstream(dir + "/frame_000013.png.partial.png") << "png";
  ASSERT_EQ(RunFiguresCommand(dir, FigureOptions{}, out, err), 0) << err.str();
  std::ifstream html2(dir + "/report.html");
  const std::string page2((std::istreambuf_iterator<char>(html2)), std::istreambuf_iterator<char>());
  EXPECT_NE(page2.find("src=\"frame_000012.png\""), std::string::npos);
  EXPECT_NE(page2.find("Frame 000012 as the run saw it"), std::string::npos);
  EXPECT_EQ(page2.find("frame_000013"), std::string::npos);
  fs::remove_all(dir);
}

TEST_F(Figures, SpeedsAreDrawnWithTheirOneSigmaBand) {
  const std::string dir = MakeResults("band", true);
  const RunResults results = ReadRunResults(dir);
  int with_sigma = 0;
  for (const auto& s : results.speeds) with_sigma += s.estimated && s.sigma_mps > 0.0;
  ASSERT_GT(with_sigma, 20);
  std::ostringstream out, err;
  ASSERT_EQ(RunFiguresCommand(dir, FigureOptions{}, out, err), 0) << err.str();
  const double banded = NonWhiteFraction(*Load(dir + "/speeds.png"));
  // The same speeds without their sigma (a file written before the column existed still reads).
  std::ifstream in(dir + "/object_speeds.csv");
  std::ostringstream without;
  for (std::string line; std::getline(in, line);) {
    size_t end = 0;  // after the fifth field: the columns before speed_sigma_mps
    for (int field = 0; field < 5; ++field) end = line.find(',', end) + 1;
    without << line.substr(0, end - 1) << '\n';
  }
  in.close();
  std::ofstream(dir + "/object_speeds.csv") << without.str();
  ASSERT_EQ(RunFiguresCommand(dir, FigureOptions{}, out, err), 0) << err.str();
  EXPECT_GT(banded, NonWhiteFraction(*Load(dir + "/speeds.png")) + 0.001);
  fs::remove_all(dir);
}

TEST_F(Figures, WithoutXvfbItSaysSoAndFailsCleanly) {
  const std::string dir = MakeResults("noxvfb");
  const char* path = std::getenv("PATH");
  const std::string saved_path = path ? path : "";
  ::setenv("PATH", "/nonexistent", 1);
  std::ostringstream out, err;
  const int code = RunFiguresCommand(dir, FigureOptions{}, out, err);
  ::setenv("PATH", saved_path.c_str(), 1);
  EXPECT_EQ(code, 3);
  EXPECT_NE(err.str().find("Xvfb is not installed"), std::string::npos) << err.str();
  EXPECT_FALSE(fs::exists(dir + "/trajectory.png"));
  fs::remove_all(dir);
}

TEST_F(Figures, OversizedFiguresAreRefusedUpFront) {
  // --scale 8 --width 8000 --height 8000 (each within its range) died on an X error.
  const std::string dir = MakeResults("oversized");
  FigureOptions huge;
  huge.scale = 8.0;
  huge.width = huge.height = 8000;
  std::ostringstream out, err;
  EXPECT_EQ(RunFiguresCommand(dir, huge, out, err), 2);
  EXPECT_NE(err.str().find("figures of 64000x64000 pixels (size times --scale): at most 16384 on a side"),
            std::string::npos)
      << err.str();
  EXPECT_FALSE(fs::exists(dir + "/trajectory.png"));
  fs::remove_all(dir);
}

std::set<pid_t> XvfbProcesses() {
  std::set<pid_t> pids;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename();
    if (name.empty() || !std::all_of(name.begin(), name.end(), ::isdigit)) continue;
    std::ifstream comm(entry.path() / "comm");
    std::string command;
    if (std::getline(comm, command) && command == "Xvfb") pids.insert(std::stoi(name));
  }
  return pids;
}

TEST_F(Figures, OurXvfbDoesNotOutliveUsWhenWeAreKilledWhileDrawing) {
  // SIGTERM while drawing left dslam's own Xvfb running with parent 1.
  const std::string dir = MakeResults("killed_while_drawing");
  const std::set<pid_t> before = XvfbProcesses();
  // Large figures: long enough to be killed in the middle.
  test::Process figures({"figures", dir, "--scale", "4", "--width", "4000", "--height", "4000"},
                        test::TempPath("figures_killed.log"));
  std::set<pid_t> ours;
  for (int i = 0; i < 200 && ours.empty(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    for (pid_t p : XvfbProcesses())
      if (!before.count(p)) ours.insert(p);
  }
  ASSERT_FALSE(ours.empty()) << "dslam figures started no Xvfb";
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  figures.signal(SIGKILL);  // no handler runs: only the kernel can stop the Xvfb
  figures.wait(std::chrono::seconds(10));
  bool gone = false;
  for (int i = 0; i < 100 && !gone; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    gone = true;
    for (pid_t p : ours) gone = gone && ::kill(p, 0) != 0;
  }
  EXPECT_TRUE(gone) << "Xvfb outlived the dslam that started it";
  fs::remove_all(dir);
}

TEST_F(Figures, MissingOrCorruptResultsAreClearErrors) {
  std::ostringstream out, err;
  EXPECT_EQ(RunFiguresCommand("/nonexistent/results", FigureOptions{}, out, err), 2);
  EXPECT_NE(err.str().find("does not exist"), std::string::npos);
  const std::string dir = MakeResults("corrupt");
  std::ofstream(dir + "/object_speeds.csv") << "frame,object_id,is_dynamic,est_speed_mps,gt_speed_mps\n3,1,1\n";
  err.str("");
  EXPECT_EQ(RunFiguresCommand(dir, FigureOptions{}, out, err), 2);
  EXPECT_NE(err.str().find("object_speeds.csv:2: expected 5 fields"), std::string::npos) << err.str();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dslam
