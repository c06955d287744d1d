// `dslam run` killed mid-sequence (SIGKILL: no handler runs) leaves every frame that had left the
// smoother's window on disk, in complete lines equal to those of an uninterrupted run; stopped by SIGTERM or
// SIGINT at any moment it ends by that signal (the shell's 128 + n) with every file on whole rows.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <tuple>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "support/child_process.h"
#include "support/rendered_city.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
using namespace std::chrono_literals;

std::vector<std::string> Lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  return lines;
}

std::vector<std::string> RunArgs(const std::string& dataset, const std::string& out) {
  return {"run", "--dataset", dataset, "--out", out, "--methods", "ours", "--no-figures", "--quiet"};
}

TEST(RunSigkill, LeavesEveryFrameThatLeftTheWindowOnDisk) {
  const std::string dataset = test::RenderedCity("sigkill_city", 40);
  const std::string full = test::TempPath("sigkill_full"), killed = test::TempPath("sigkill_killed");
  {
    test::Process run(RunArgs(dataset, full), test::TempPath("sigkill_full.log"));
    ASSERT_EQ(run.wait(300s), 0) << test::ReadFile(test::TempPath("sigkill_full.log"));
  }
  const std::vector<std::string> reference = Lines(full + "/camera_ours.tum");
  ASSERT_EQ(reference.size(), 40u);

  test::Process run(RunArgs(dataset, killed), test::TempPath("sigkill_killed.log"));
  const std::string streamed = killed + "/camera_ours.tum";
  const auto deadline = std::chrono::steady_clock::now() + 300s;
  while (Lines(streamed).size() < 5 && std::chrono::steady_clock::now() < deadline && run.running())
    std::this_thread::sleep_for(2ms);
  run.signal(SIGKILL);
  run.wait(30s);

  const std::vector<std::string> cameras = Lines(streamed);
  const std::vector<std::string> online = Lines(killed + "/camera_ours_online.tum");
  ASSERT_GE(cameras.size(), 5u);
  ASSERT_LT(cameras.size(), 40u) << "the run finished before it could be killed";
  // Final poses are final: the same rows as the uninterrupted run, each line whole.
  for (size_t i = 0; i < cameras.size(); ++i) EXPECT_EQ(cameras[i], reference[i]) << i;
  // What is missing is at most the window (10 frames, the newest of which is the frame just estimated) and
  // the frame being added.
  EXPECT_LE(online.size(), cameras.size() + 10) << online.size() << " frames estimated, " << cameras.size() << " final";
  EXPECT_GE(online.size(), cameras.size() + 8);  // 8: killed between a camera and its frame's online pose
  // The other streamed tables are there, whole lines with every column.
  const std::vector<std::string> speeds = Lines(killed + "/object_speeds.csv");
  ASSERT_GE(speeds.size(), 2u);
  EXPECT_EQ(speeds[0],
            "frame,object_id,is_dynamic,est_speed_mps,gt_speed_mps,speed_sigma_mps,centroid_x_m,centroid_y_m,"
            "centroid_z_m,box_x,box_y,box_w,box_h");
  for (const std::string& row : speeds) EXPECT_EQ(std::count(row.begin(), row.end(), ','), 12) << row;
  // The front-end's log is cut between rows, never inside one.
  const std::string log = test::ReadFile(killed + "/frontend.csv");
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(log.back(), '\n');
  for (const std::string& row : Lines(killed + "/frontend.csv")) EXPECT_EQ(std::count(row.begin(), row.end(), ','), 12) << row;
}


// Every CSV row has its header's columns and every trajectory row 8 (TUM) or 12 (KITTI) numbers; every file
// ends on a newline.
void ExpectWholeRows(const std::string& dir) {
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string path = entry.path().string(), ext = entry.path().extension().string();
    if (ext != ".csv" && ext != ".tum" && ext != ".kitti") continue;
    const std::string text = test::ReadFile(path);
    if (text.empty()) continue;
    EXPECT_EQ(text.back(), '\n') << path << " ends inside a row";
    const std::vector<std::string> rows = Lines(path);
    const auto fields = [](const std::string& row, char sep) { return std::count(row.begin(), row.end(), sep) + 1; };
    for (const std::string& row : rows) {
      const auto want = ext == ".csv" ? fields(rows[0], ',') : ext == ".tum" ? 8 : 12;
      EXPECT_EQ(fields(row, ext == ".csv" ? ',' : ' '), want) << path << ": " << row;
    }
  }
}

TEST(RunSignals, SigtermOrSigintAtAnyMomentEndTheRunByTheSignalOnWholeRows) {
  const std::string dataset = test::RenderedCity("sigkill_city", 40);
  // The signal, and how many frames' online poses are on disk when it is sent.
  for (const auto& [sig, after_frames] : {std::tuple{SIGTERM, 1}, std::tuple{SIGINT, 6}, std::tuple{SIGTERM, 14},
                                          std::tuple{SIGINT, 25}}) {
    const std::string out = test::TempPath("signal_" + std::to_string(sig) + "_" + std::to_string(after_frames));
    test::Process run(RunArgs(dataset, out), out + ".log");
    const auto deadline = std::chrono::steady_clock::now() + 300s;
    while (Lines(out + "/camera_ours_online.tum").size() < static_cast<size_t>(after_frames) &&
           std::chrono::steady_clock::now() < deadline && run.running())
      std::this_thread::sleep_for(1ms);
    run.signal(sig);
    EXPECT_EQ(run.wait(60s), -1) << "exited instead of ending by the signal " << sig;
    EXPECT_EQ(run.terminatingSignal(), sig) << test::ReadFile(out + ".log");
    ExpectWholeRows(out);
  }
}

}  // namespace
}  // namespace dslam
