#include "render/figures.h"

#include <vtkActor.h>
#include <vtkAxis.h>
#include <vtkBrush.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkChartLegend.h>
#include <vtkChartMatrix.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotArea.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyLine.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "geometry/velocity.h"

namespace dslam {
namespace {

using Series = std::vector<std::pair<double, double>>;

int Px(double v, const FigureOptions& o) { return static_cast<int>(std::lround(v * o.scale)); }

void SavePng(vtkRenderWindow* window, const std::string& png) {
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(png.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0) throw std::runtime_error("cannot write " + png);
}

void SetupView(vtkContextView* view, const FigureOptions& o) {
  view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  view->GetRenderWindow()->SetOffScreenRendering(1);
  view->GetRenderWindow()->SetSize(Px(o.width, o), Px(o.height, o));
  view->GetRenderWindow()->SetMultiSamples(0);  // identical pixels run to run
}

void StyleChart(vtkChart* chart, const std::string& title, const std::string& x_title, const std::string& y_title,
                const FigureOptions& o, int base_font) {
  chart->SetTitle(title);
  chart->GetTitleProperties()->SetFontSize(Px(base_font + 6, o));
  chart->GetTitleProperties()->BoldOn();
  for (int a : {vtkAxis::BOTTOM, vtkAxis::LEFT}) {
    vtkAxis* axis = chart->GetAxis(a);
    axis->SetTitle(a == vtkAxis::BOTTOM ? x_title : y_title);
    axis->GetTitleProperties()->SetFontSize(Px(base_font + 2, o));
    axis->GetLabelProperties()->SetFontSize(Px(base_font, o));
  }
}

vtkPlot* AddLine(vtkChartXY* chart, const Series& data, const std::array<unsigned char, 3>& colour, float width,
                 bool dashed, const std::string& label) {
  if (data.size() < 2) return nullptr;  // nothing to draw (VTK complains about a line of fewer points)
  vtkNew<vtkTable> table;
  vtkNew<vtkFloatArray> x, y;
  x->SetName("x");
  y->SetName(label.empty() ? "y" : label.c_str());
  table->AddColumn(x);
  table->AddColumn(y);
  table->SetNumberOfRows(static_cast<vtkIdType>(data.size()));
  for (size_t i = 0; i < data.size(); ++i) {
    table->SetValue(static_cast<vtkIdType>(i), 0, data[i].first);
    table->SetValue(static_cast<vtkIdType>(i), 1, data[i].second);
  }
  vtkPlot* plot = chart->AddPlot(vtkChart::LINE);
  plot->SetInputData(table, 0, 1);
  plot->SetColor(colour[0], colour[1], colour[2], 255);
  plot->SetWidth(width);
  if (dashed) plot->GetPen()->SetLineType(vtkPen::DASH_LINE);
  plot->SetLabel(label);
  plot->SetLegendVisibility(!label.empty());
  return plot;
}

// A filled band between low and high (one per x), light in the colour: an estimate's +-1 sigma.
void AddBand(vtkChartXY* chart, const std::vector<std::array<double, 3>>& x_low_high,
             const std::array<unsigned char, 3>& colour, const std::string& label) {
  if (x_low_high.size() < 2) return;
  vtkNew<vtkTable> table;
  vtkNew<vtkFloatArray> x, low, high;
  x->SetName("x");
  low->SetName("low");
  high->SetName("high");
  table->AddColumn(x);
  table->AddColumn(low);
  table->AddColumn(high);
  table->SetNumberOfRows(static_cast<vtkIdType>(x_low_high.size()));
  for (size_t i = 0; i < x_low_high.size(); ++i)
    for (int c = 0; c < 3; ++c) table->SetValue(static_cast<vtkIdType>(i), c, x_low_high[i][c]);
  auto* area = vtkPlotArea::SafeDownCast(chart->AddPlot(vtkChart::AREA));
  if (!area) return;
  area->SetInputData(table);
  area->SetInputArray(0, "x");
  area->SetInputArray(1, "low");
  area->SetInputArray(2, "high");
  area->GetBrush()->SetColor(colour[0], colour[1], colour[2], 70);
  area->SetLabel(label);
  area->SetLegendVisibility(!label.empty());
}

std::string Fixed(double v, int precision) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << v;
  return s.str();
}

// Mean estimated and ground-truth speed (km/h) per object over its estimated frame pairs.
std::map<int, std::pair<double, double>> MeanSpeedsKmh(const RunResults& r) {
  std::map<int, std::pair<double, double>> sums;
  std::map<int, int> counts;
  for (const auto& s : r.speeds) {
    if (!s.estimated) continue;
    sums[s.object_id].first += s.est_mps;
    sums[s.object_id].second += s.gt_mps;
    ++counts[s.object_id];
  }
  for (auto& [id, v] : sums) v = {v.first / counts[id] * kMpsToKmh, v.second / counts[id] * kMpsToKmh};
  return sums;
}

// Objects estimated as moving at least once, in id order (the palette index follows it); parked
// objects only clutter the trajectory and speed plots (they are in the map, in grey).
std::vector<int> MovingObjects(const RunResults& r) {
  std::set<int> ids;
  for (const auto& s : r.speeds)
    if (s.estimated && s.is_dynamic) ids.insert(s.object_id);
  return {ids.begin(), ids.end()};
}

// A title across the top of a multi-panel figure.
void AddFigureTitle(vtkContextView* view, const std::string& text, const FigureOptions& o) {
  vtkNew<vtkTextActor> title;
  title->SetInput(text.c_str());
  title->GetTextProperty()->SetFontSize(Px(20, o));
  title->GetTextProperty()->BoldOn();
  title->GetTextProperty()->SetColor(0.0, 0.0, 0.0);
  title->SetDisplayPosition(Px(20, o), Px(o.height - 32, o));
  view->GetRenderer()->AddActor2D(title);
}
}  // namespace

std::array<unsigned char, 3> ObjectColour(int index) {
  static const std::array<unsigned char, 3> palette[] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44},
                                                         {148, 103, 189}, {140, 86, 75},  {227, 119, 194},
                                                         {188, 189, 34},  {23, 190, 207}, {127, 127, 127},
                                                         {0, 80, 160}};
  return palette[index % 10];
}

PlotArea DrawTrajectoryFigure(const RunResults& r, const std::string& png, const FigureOptions& o) {
  vtkNew<vtkContextView> view;
  SetupView(view, o);
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  StyleChart(chart, "Trajectories (top view): " + r.title(), "x (m)", "z (m)", o, 14);
  chart->SetShowLegend(true);
  chart->GetLegend()->GetLabelProperties()->SetFontSize(Px(13, o));

  double xmin = 1e300, xmax = -1e300, zmin = 1e300, zmax = -1e300;
  auto extend = [&](double x, double z) {
    xmin = std::min(xmin, x), xmax = std::max(xmax, x), zmin = std::min(zmin, z), zmax = std::max(zmax, z);
  };
  Series gt, est;
  for (const auto& T : r.camera_gt) gt.emplace_back(T.translation().x(), T.translation().z());
  for (const auto& T : r.camera_est) est.emplace_back(T.translation().x(), T.translation().z());
  for (const auto& p : gt.empty() ? est : gt) extend(p.first, p.second);
  if (!gt.empty()) AddLine(chart, gt, kGroundTruthColour, Px(3.0, o), false, "camera ground truth");
  AddLine(chart, est, kEstimateColour, Px(2.0, o), false, "camera estimate (" + r.method + ")");

  std::map<int, std::map<int, Vec3>> centroids;  // object -> frame -> ground-truth centroid
  for (const auto& c : r.centroids)
    if (c.observed) centroids[c.object_id][c.frame] = c.c_world;
  std::map<int, std::map<int, const RunResults::MotionRow*>> motions;
  for (const auto& m : r.motions)
    if (m.estimated) motions[m.object_id][m.frame] = &m;
  const auto speeds = MeanSpeedsKmh(r);
  const auto objects = MovingObjects(r);
  for (size_t i = 0; i < objects.size(); ++i) {
    const int id = objects[i];
    const auto colour = ObjectColour(static_cast<int>(i));
    Series truth;
    for (const auto& [k, c] : centroids[id]) {
      truth.emplace_back(c.x(), c.z());
      extend(c.x(), c.z());
    }
    AddLine(chart, truth, colour, Px(2.0, o), true, "");
    // Estimated track: start from the ground-truth centroid, chain the estimated motions; restart
    // from the ground truth after a gap.
    Series track;
    Vec3 c = Vec3::Zero();
    int last = -2;
    for (const auto& [k, m] : motions[id]) {
      if (k != last + 1) {
        const auto it = centroids[id].find(k - 1);
        if (it == centroids[id].end()) continue;
        if (!track.empty()) {
          AddLine(chart, track, colour, Px(2.5, o), false, "");
          track.clear();
        }
        c = it->second;
        track.emplace_back(c.x(), c.z());
      }
      c = m->H_est * c;
      track.emplace_back(c.x(), c.z());
      last = k;
    }
    const auto sp = speeds.find(id);
    const std::string label = "object " + std::to_string(id) +
                              (sp == speeds.end() ? "" : ": " + Fixed(sp->second.first, 1) + " / " +
                                                             Fixed(sp->second.second, 1) + " km/h (est / gt)");
    if (!track.empty()) AddLine(chart, track, colour, Px(2.5, o), false, label);
  }

  // Equal axes: render once to learn the plot area, then widen one range to its aspect ratio.
  view->GetRenderWindow()->Render();
  const int w = std::max(1, chart->GetPoint2()[0] - chart->GetPoint1()[0]);
  const int h = std::max(1, chart->GetPoint2()[1] - chart->GetPoint1()[1]);
  const double pad = 0.05 * std::max({xmax - xmin, zmax - zmin, 1.0});
  xmin -= pad, xmax += pad, zmin -= pad, zmax += pad;
  const double m_per_px = std::max((xmax - xmin) / w, (zmax - zmin) / h);
  const double xc = 0.5 * (xmin + xmax), zc = 0.5 * (zmin + zmax);
  PlotArea area;
  area.xmin = xc - 0.5 * m_per_px * w, area.xmax = xc + 0.5 * m_per_px * w;
  area.ymin = zc - 0.5 * m_per_px * h, area.ymax = zc + 0.5 * m_per_px * h;
  chart->GetAxis(vtkAxis::BOTTOM)->SetBehavior(vtkAxis::FIXED);
  chart->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
  chart->GetAxis(vtkAxis::BOTTOM)->SetRange(area.xmin, area.xmax);
  chart->GetAxis(vtkAxis::LEFT)->SetRange(area.ymin, area.ymax);
  SavePng(view->GetRenderWindow(), png);
  area.x0 = chart->GetPoint1()[0], area.y0 = chart->GetPoint1()[1];
  area.x1 = chart->GetPoint2()[0], area.y1 = chart->GetPoint2()[1];
  return area;
}

void DrawSpeedsFigure(const RunResults& r, const std::string& png, const FigureOptions& o) {
  std::map<int, Series> est, gt;
  std::map<int, std::vector<std::array<double, 3>>> band;  // estimate +- 1 sigma, km/h
  for (const auto& s : r.speeds) {
    if (r.has_ground_truth) gt[s.object_id].emplace_back(s.frame, s.gt_mps * kMpsToKmh);
    if (s.estimated) est[s.object_id].emplace_back(s.frame, s.est_mps * kMpsToKmh);
    if (s.estimated && s.sigma_mps > 0.0)
      band[s.object_id].push_back({static_cast<double>(s.frame), std::max(0.0, s.est_mps - s.sigma_mps) * kMpsToKmh,
                                   (s.est_mps + s.sigma_mps) * kMpsToKmh});
  }
  // The moving objects with most estimates, at most 16 panels.
  std::vector<int> ids = MovingObjects(r);
  std::stable_sort(ids.begin(), ids.end(), [&](int a, int b) { return est[a].size() > est[b].size(); });
  if (ids.size() > 16) ids.resize(16);
  std::sort(ids.begin(), ids.end());

  vtkNew<vtkContextView> view;
  SetupView(view, o);
  vtkNew<vtkChartMatrix> matrix;
  view->GetScene()->AddItem(matrix);
  const int n = std::max<int>(1, static_cast<int>(ids.size()));
  const int cols = static_cast<int>(std::ceil(std::sqrt(n * 1.6)));
  const int rows = (n + cols - 1) / cols;
  matrix->SetSize(vtkVector2i(cols, rows));
  matrix->SetGutter(vtkVector2f(Px(60, o), Px(70, o)));
  matrix->SetBorders(Px(70, o), Px(60, o), Px(30, o), Px(80, o));
  const auto objects = MovingObjects(r);
  for (int i = 0; i < static_cast<int>(ids.size()); ++i) {
    const int id = ids[i];
    auto* chart = vtkChartXY::SafeDownCast(matrix->GetChart(vtkVector2i(i % cols, rows - 1 - i / cols)));
    const int palette = static_cast<int>(std::find(objects.begin(), objects.end(), id) - objects.begin());
    StyleChart(chart, "object " + std::to_string(id), "frame", "speed (km/h)", o, 11);
    AddBand(chart, band[id], ObjectColour(palette), "estimate +- 1 sigma");
    if (!gt[id].empty()) AddLine(chart, gt[id], kGroundTruthColour, Px(2.0, o), true, "ground truth");
    AddLine(chart, est[id], ObjectColour(palette), Px(2.0, o), false, "estimate");
    chart->SetShowLegend(i == 0);
  }
  AddFigureTitle(view,
                 (r.has_ground_truth ? "Object speeds: estimate (solid) vs ground truth (dashed) - "
                                     : "Object speeds (no ground truth) - ") +
                     r.title(),
                 o);
  SavePng(view->GetRenderWindow(), png);
}

void DrawErrorsFigure(const RunResults& r, const std::string& png, const FigureOptions& o) {
  Series cam_t, cam_r, obj_t;
  for (size_t k = 1; k < r.camera_gt.size(); ++k) {
    const SE3 e = (r.camera_gt[k - 1].inverse() * r.camera_gt[k]).inverse() * (r.camera_est[k - 1].inverse() * r.camera_est[k]);
    cam_t.emplace_back(k, e.translation().norm() * 100.0);
    cam_r.emplace_back(k, e.angle() * kRadToDeg);
  }
  std::map<int, std::pair<double, int>> per_frame;
  for (const auto& m : r.motions) {
    if (!m.estimated) continue;
    auto& acc = per_frame[m.frame];
    acc.first += (m.H_gt.inverse() * m.H_est).translation().norm() * 100.0;
    ++acc.second;
  }
  for (const auto& [k, acc] : per_frame) obj_t.emplace_back(k, acc.first / acc.second);

  vtkNew<vtkContextView> view;
  SetupView(view, o);
  vtkNew<vtkChartMatrix> matrix;
  view->GetScene()->AddItem(matrix);
  matrix->SetSize(vtkVector2i(1, 3));
  matrix->SetGutter(vtkVector2f(Px(40, o), Px(70, o)));
  matrix->SetBorders(Px(80, o), Px(60, o), Px(30, o), Px(80, o));
  struct Panel {
    Series* data;
    const char* title;
    const char* y;
    std::array<unsigned char, 3> colour;
  };
  const Panel panels[3] = {
      {&cam_t, "Camera relative translation error per frame", "error (cm)", kEstimateColour},
      {&cam_r, "Camera relative rotation error per frame", "error (deg)", kEstimateColour},
      {&obj_t, "Object motion error per frame (mean over objects, world frame)", "error (cm)", ObjectColour(0)}};
  for (int i = 0; i < 3; ++i) {
    auto* chart = vtkChartXY::SafeDownCast(matrix->GetChart(vtkVector2i(0, 2 - i)));
    StyleChart(chart, panels[i].title, "frame", panels[i].y, o, 12);
    AddLine(chart, *panels[i].data, panels[i].colour, Px(2.0, o), false, r.method);
  }
  AddFigureTitle(view, "Errors per frame - " + r.title(), o);
  SavePng(view->GetRenderWindow(), png);
}

void DrawMapFigure(const RunResults& r, const std::string& png, const FigureOptions& o) {
  vtkNew<vtkPoints> points;
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetNumberOfComponents(3);
  colours->SetName("colour");
  vtkNew<vtkCellArray> vertices;
  const auto objects = MovingObjects(r);
  for (const auto& p : r.map_points) {
    std::array<unsigned char, 3> c = {150, 150, 150};
    const auto it = std::find(objects.begin(), objects.end(), p.object_id);
    if (it != objects.end()) c = ObjectColour(static_cast<int>(it - objects.begin()));  // parked: stays grey
    const vtkIdType id = points->InsertNextPoint(p.p_world.x(), p.p_world.y(), p.p_world.z());
    vertices->InsertNextCell(1, &id);
    colours->InsertNextTypedTuple(c.data());
  }
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(points);
  cloud->SetVerts(vertices);
  cloud->GetPointData()->SetScalars(colours);
  vtkNew<vtkPolyDataMapper> cloud_mapper;
  cloud_mapper->SetInputData(cloud);
  vtkNew<vtkActor> cloud_actor;
  cloud_actor->SetMapper(cloud_mapper);
  cloud_actor->GetProperty()->SetPointSize(std::max(1.0, 2.0 * o.scale));

  vtkNew<vtkPoints> path_points;
  for (const auto& T : r.camera_est) path_points->InsertNextPoint(T.translation().data());
  vtkNew<vtkPolyLine> line;
  line->GetPointIds()->SetNumberOfIds(path_points->GetNumberOfPoints());
  for (vtkIdType i = 0; i < path_points->GetNumberOfPoints(); ++i) line->GetPointIds()->SetId(i, i);
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell(line);
  vtkNew<vtkPolyData> path;
  path->SetPoints(path_points);
  path->SetLines(lines);
  vtkNew<vtkPolyDataMapper> path_mapper;
  path_mapper->SetInputData(path);
  vtkNew<vtkActor> path_actor;
  path_actor->SetMapper(path_mapper);
  path_actor->GetProperty()->SetColor(kEstimateColour[0] / 255.0, kEstimateColour[1] / 255.0, kEstimateColour[2] / 255.0);
  path_actor->GetProperty()->SetLineWidth(3.0 * o.scale);

  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1.0, 1.0, 1.0);
  renderer->AddActor(cloud_actor);
  renderer->AddActor(path_actor);
  vtkNew<vtkTextActor> title;
  title->SetInput(("Map: static structure (grey), object points by object, camera path (red) - " + r.title()).c_str());
  title->GetTextProperty()->SetFontSize(Px(20, o));
  title->GetTextProperty()->SetColor(0.0, 0.0, 0.0);
  title->SetDisplayPosition(Px(20, o), Px(o.height - 40, o));
  renderer->AddActor2D(title);

  // Look from behind and above the start (y is down), at the middle of the path.
  double bounds[6];
  cloud->GetBounds(bounds);
  const Vec3 centre = r.camera_est.empty() ? Vec3::Zero() : r.camera_est[r.camera_est.size() / 2].translation();
  const double extent = std::max({bounds[1] - bounds[0], bounds[5] - bounds[4], 20.0});
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetFocalPoint(centre.x(), centre.y(), centre.z());
  camera->SetPosition(centre.x() - 0.35 * extent, centre.y() - 0.6 * extent, centre.z() - 0.55 * extent);
  camera->SetViewUp(0.0, -1.0, 0.0);
  camera->SetViewAngle(40.0);
  renderer->ResetCameraClippingRange();

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(Px(o.width, o), Px(o.height, o));
  window->AddRenderer(renderer);
  SavePng(window, png);
}

void DrawBarFigure(const std::string& title, const std::vector<std::string>& categories,
                   const std::vector<BarPanel>& panels, const std::string& png, const FigureOptions& o) {
  if (categories.empty() || panels.empty()) throw std::invalid_argument("a bar figure needs categories and panels");
  vtkNew<vtkContextView> view;
  SetupView(view, o);
  vtkNew<vtkChartMatrix> matrix;
  view->GetScene()->AddItem(matrix);
  const int n = static_cast<int>(panels.size());
  matrix->SetSize(vtkVector2i(1, n));
  matrix->SetGutter(vtkVector2f(Px(40, o), Px(80, o)));
  matrix->SetBorders(Px(90, o), Px(80, o), Px(30, o), Px(80, o));
  vtkNew<vtkDoubleArray> positions;
  vtkNew<vtkStringArray> labels;
  for (size_t c = 0; c < categories.size(); ++c) {
    positions->InsertNextValue(static_cast<double>(c));
    labels->InsertNextValue(categories[c]);
  }
  for (int p = 0; p < n; ++p) {
    const BarPanel& panel = panels[static_cast<size_t>(p)];
    auto* chart = vtkChartXY::SafeDownCast(matrix->GetChart(vtkVector2i(0, n - 1 - p)));
    StyleChart(chart, panel.title, "", panel.y_title, o, 12);
    chart->SetShowLegend(panel.series.size() > 1);
    chart->SetBarWidthFraction(0.8f);
    for (size_t s = 0; s < panel.series.size(); ++s) {
      vtkNew<vtkTable> table;
      vtkNew<vtkFloatArray> x, y;
      x->SetName("x");
      y->SetName(panel.series[s].c_str());
      table->AddColumn(x);
      table->AddColumn(y);
      table->SetNumberOfRows(static_cast<vtkIdType>(categories.size()));
      for (size_t c = 0; c < categories.size(); ++c) {
        const double v = c < panel.values.size() && s < panel.values[c].size() ? panel.values[c][s] : 0.0;
        table->SetValue(static_cast<vtkIdType>(c), 0, static_cast<double>(c));
        table->SetValue(static_cast<vtkIdType>(c), 1, std::isfinite(v) ? v : 0.0);
      }
      vtkPlot* bars = chart->AddPlot(vtkChart::BAR);
      bars->SetInputData(table, 0, 1);
      const auto colour = s == 0 ? kEstimateColour : ObjectColour(static_cast<int>(s) + 1);
      bars->SetColor(colour[0], colour[1], colour[2], 255);
      bars->SetLabel(panel.series[s]);
    }
    vtkAxis* x_axis = chart->GetAxis(vtkAxis::BOTTOM);
    x_axis->SetCustomTickPositions(positions, labels);
    x_axis->SetBehavior(vtkAxis::FIXED);
    x_axis->SetRange(-0.6, static_cast<double>(categories.size()) - 0.4);
    chart->GetAxis(vtkAxis::LEFT)->SetMinimum(0.0);
    chart->GetAxis(vtkAxis::LEFT)->SetMinimumLimit(0.0);
  }
  AddFigureTitle(view, title, o);
  SavePng(view->GetRenderWindow(), png);
}

}  // namespace dslam
