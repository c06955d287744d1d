#include "app/figures_command.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <exception>

#include "output/report_html.h"
#include "render/headless_display.h"

namespace dslam {

int RunFiguresCommand(const std::string& dir, const FigureOptions& options, std::ostream& out, std::ostream& err) {
  try {
    if (!(options.scale > 0.0 && options.scale <= 8.0)) throw std::invalid_argument("--scale must be in (0, 8]");
    if (options.width < 200 || options.height < 150) throw std::invalid_argument("figure size must be at least 200x150");
    // A bigger picture than this is gigabytes of pixels and beyond what the off-screen X server renders.
    constexpr double kMaxSidePx = 16384;
    if (options.width * options.scale > kMaxSidePx || options.height * options.scale > kMaxSidePx)
      throw std::invalid_argument("figures of " + std::to_string(static_cast<long>(options.width * options.scale)) + "x" +
                                  std::to_string(static_cast<long>(options.height * options.scale)) +
                                  " pixels (size times --scale): at most 16384 on a side");
    const auto start = std::chrono::steady_clock::now();
    const RunResults results = ReadRunResults(dir);
    std::string error;
    const auto display = HeadlessDisplay::Acquire(&error);
    if (!display) {
      err << "dslam figures: error: " << error << std::endl;
      return 3;
    }
    // The error plots need ground truth, the speeds object estimates; every other figure is drawn anyway.
    std::vector<std::string> files = {"trajectory.png", "map.png"};
    DrawTrajectoryFigure(results, dir + "/trajectory.png", options);
    if (results.has_objects) {
      DrawSpeedsFigure(results, dir + "/speeds.png", options);
      files.insert(files.begin() + 1, "speeds.png");
    }
    if (results.has_ground_truth) {
      DrawErrorsFigure(results, dir + "/errors.png", options);
      files.insert(files.end() - 1, "errors.png");
    }
    DrawMapFigure(results, dir + "/map.png", options);
    // Frames with the objects drawn on them, when the run wrote some (dslam run on images).
    std::vector<std::string> frames;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("frame_", 0) == 0 && entry.path().extension() == ".png" && name.find(".partial") == std::string::npos)
        frames.push_back(name);
    }
    std::sort(frames.begin(), frames.end());
    files.insert(files.end(), frames.begin(), frames.end());
    WriteReportHtml(results, files, dir + "/report.html");
    std::string list;
    for (const auto& f : files) list += f + ", ";
    out << "Figures written to " << dir << " (" << list << "report.html) in "
        << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s" << std::endl;
    return 0;
  } catch (const std::exception& e) {
    err << "dslam figures: error: " << e.what() << std::endl;
    return 2;
  }
}

}  // namespace dslam
