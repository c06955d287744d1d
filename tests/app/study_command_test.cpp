// `dslam study` on a tiny rendered scene: every setting with every method in study.csv, the tracking
// comparison in tracking.csv, both figures; and a clear error for a scene rendered without what it needs.
#include "app/study_command.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <opencv2/imgproc.hpp>

#include "data/image_codec.h"
#include "support/no_display.h"
#include "support/rendered_city.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

std::vector<std::vector<std::string>> ReadCsv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    rows.push_back(cells);
  }
  return rows;
}

TEST(StudyCommand, WritesEverySettingForEveryMethodTheTrackingComparisonAndBothFigures) {
  const std::string dataset = test::RenderedCity("study_city", 8, 1, true, 0.5);
  test::ScopedNoDisplay no_display;
  StudyCommandOptions options;
  options.dataset_dir = dataset;
  options.frames = 0;
  options.out_dir = test::TempPath("study_out");
  options.quiet = true;
  std::ostringstream out, err;
  ASSERT_EQ(RunStudyCommand(options, out, err), 0) << err.str();

  const auto study = ReadCsv(options.out_dir + "/study.csv");
  ASSERT_EQ(study.size(), 1u + 10u * 3u);
  ASSERT_EQ(study[0].size(), 14u);
  EXPECT_EQ(study[0][0], "component");
  std::map<std::string, std::map<std::string, std::vector<std::string>>> rows;  // setting -> method -> row
  for (size_t i = 1; i < study.size(); ++i) {
    ASSERT_EQ(study[i].size(), 14u) << i;
    rows[study[i][1]][study[i][2]] = study[i];
  }
  for (const char* setting : {"exact", "depth 0.02 m", "depth 0.04 m", "depth 0.06 m", "stereo SGBM", "degraded masks",
                              "LK", "DIS", "ORB matching", "stereo+degraded+LK"}) {
    ASSERT_EQ(rows[setting].size(), 3u) << setting;
    EXPECT_FALSE(rows[setting]["ours"][3].empty()) << setting;  // RTE
    EXPECT_FALSE(rows[setting]["ours"][8].empty()) << setting;  // OMSE
    EXPECT_TRUE(rows[setting]["static_only"][8].empty()) << setting;  // no objects
  }
  // The segmentation score is reported with the degraded runs only.
  EXPECT_FALSE(rows["degraded masks"]["ours"][12].empty());
  EXPECT_TRUE(rows["exact"]["ours"][12].empty());
  const double miou = std::stod(rows["degraded masks"]["ours"][12]);
  EXPECT_GT(miou, 0.2);
  EXPECT_LT(miou, 0.95);
  // Exact inputs beat the stereo depth on the camera and the objects.
  EXPECT_LT(std::stod(rows["exact"]["ours"][3]), std::stod(rows["stereo SGBM"]["ours"][3]));
  EXPECT_LT(std::stod(rows["exact"]["ours"][8]), std::stod(rows["stereo SGBM"]["ours"][8]));

  const auto tracking = ReadCsv(options.out_dir + "/tracking.csv");
  ASSERT_EQ(tracking.size(), 5u);
  EXPECT_EQ(tracking[1][0], "exact");
  EXPECT_EQ(tracking[1][1], "7");  // frame pairs
  EXPECT_EQ(std::stod(tracking[1][5]), 0.0);  // the exact correspondences' own EPE
  for (size_t i = 2; i < tracking.size(); ++i) EXPECT_GT(std::stod(tracking[i][5]), 0.0) << tracking[i][0];

  const std::string page = options.out_dir + "/report.html";
  ASSERT_TRUE(std::filesystem::exists(page));
  for (const char* png : {"study_effects.png", "study_tracking.png"}) {
    const cv::Mat image = dslam::ReadPngFile(options.out_dir + "/" + png, dslam::ImageDecode::kColour);
    ASSERT_FALSE(image.empty()) << png;
    EXPECT_EQ(image.cols, 1600) << png;
    cv::Mat grey;
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    EXPECT_GT(image.total() - cv::countNonZero(grey > 250), image.total() / 50) << png << " is nearly blank";
  }
}

TEST(StudyCommand, NamesWhatASceneRenderedWithoutTheStereoPairOrTheExactFlowLacks) {
  const std::string dataset = test::RenderedCity("study_city_mono", 3);
  StudyCommandOptions options;
  options.dataset_dir = dataset;
  options.out_dir = test::TempPath("study_out_mono");
  std::ostringstream out, err;
  EXPECT_EQ(RunStudyCommand(options, out, err), 2);
  EXPECT_NE(err.str().find("lacks image_1/: the study needs a scene rendered with `dslam render-scene --stereo "
                           "--exact-flow`"),
            std::string::npos)
      << err.str();
}

}  // namespace
}  // namespace dslam
