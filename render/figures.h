#pragma once
// Off-screen figures of a run, drawn with VTK (the only VTK code of the project, in one translation
// unit). Needs an X display: hold a HeadlessDisplay while calling these.

#include <array>
#include <string>
#include <vector>

#include "output/result_reader.h"

namespace dslam {

struct FigureOptions {
  int width = 1600;
  int height = 1000;
  double scale = 1.0;  // multiplies the size, line widths and fonts (print resolution)
};

// Where the data of a chart landed in the image: plot corners in pixels (origin bottom-left, as VTK
// images) and the data ranges they span; tests use it to find known trajectories.
struct PlotArea {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;
};

// Colours: ground truth black, our camera estimate red, objects from a fixed palette.
constexpr std::array<unsigned char, 3> kGroundTruthColour = {0, 0, 0};
constexpr std::array<unsigned char, 3> kEstimateColour = {214, 39, 40};
std::array<unsigned char, 3> ObjectColour(int index);

// Top-down x-z view, equal axes: camera ground truth and estimate; per object the ground-truth
// centroid track (dashed) and the track obtained by applying the estimated motions to the first
// ground-truth centroid, labelled with id and mean speed (estimated / ground truth, km/h).
PlotArea DrawTrajectoryFigure(const RunResults& r, const std::string& png, const FigureOptions& options);
// Speed (km/h) against frame per object (small multiples): estimate solid, ground truth dashed.
void DrawSpeedsFigure(const RunResults& r, const std::string& png, const FigureOptions& options);
// Per frame: camera translation and rotation error of the relative pose, and object motion error.
void DrawErrorsFigure(const RunResults& r, const std::string& png, const FigureOptions& options);
// 3D perspective render of the static map (grey), dynamic points coloured by object, camera path.
void DrawMapFigure(const RunResults& r, const std::string& png, const FigureOptions& options);

// Grouped bars, one chart per panel stacked top to bottom: per category (x) one bar per series. Missing
// values (NaN) leave a gap. Used by the front-end study (its effects and its tracking comparison).
struct BarPanel {
  std::string title, y_title;
  std::vector<std::string> series;          // legend names
  std::vector<std::vector<double>> values;  // [category][series]
};
void DrawBarFigure(const std::string& title, const std::vector<std::string>& categories,
                   const std::vector<BarPanel>& panels, const std::string& png, const FigureOptions& options);

}  // namespace dslam
