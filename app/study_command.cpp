#include "app/study_command.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>

#include "data/mask_degrader.h"
#include "frontend/tracking_comparison.h"
#include "output/report_html.h"
#include "output/result_reader.h"
#include "output/whole_file.h"
#include "pipeline/image_run.h"
#include "render/figures.h"
#include "render/headless_display.h"

namespace dslam {
namespace {

// One setting of the study: which front-end inputs are realistic.
struct Setting {
  std::string component;  // exact, depth, segmentation, tracking, all
  std::string name;       // as in the figures
  double depth_sigma_m = 0.0;
  bool stereo = false;
  bool degraded_masks = false;
  FlowMethod tracking = FlowMethod::kPrecomputed;  // the exact correspondences (render-scene --exact-flow)
};

std::vector<Setting> Settings() {
  std::vector<Setting> s = {{"exact", "exact"}};
  for (double sigma : {0.02, 0.04, 0.06}) {
    std::ostringstream name;
    name << "depth " << sigma << " m";
    s.push_back({"depth", name.str(), sigma});
  }
  s.push_back({"depth", "stereo SGBM", 0.0, true});
  s.push_back({"segmentation", "degraded masks", 0.0, false, true});
  s.push_back({"tracking", "LK", 0.0, false, false, FlowMethod::kLucasKanade});
  s.push_back({"tracking", "DIS", 0.0, false, false, FlowMethod::kDis});
  s.push_back({"tracking", "ORB matching", 0.0, false, false, FlowMethod::kOrb});
  s.push_back({"all", "stereo+degraded+LK", 0.0, true, true, FlowMethod::kLucasKanade});
  return s;
}

std::string Cell(const std::optional<double>& v) {
  if (!v || !std::isfinite(*v)) return "";
  std::ostringstream out;
  out << std::setprecision(6) << *v;
  return out.str();
}

double Value(const std::optional<double>& v) { return v ? *v : std::numeric_limits<double>::quiet_NaN(); }

// The ground truth with the ids the degraded segmenter gave: each id it shows in frame k stands for the
// exact object it came from (a switched or split id is that object again under another name), so that
// the evaluation compares each estimated object with the motion of the object its points belong to.
KittiGroundTruthSequence GroundTruthWithDegradedIds(const KittiGroundTruthSequence& exact,
                                                    const std::vector<std::map<int, int>>& source_of) {
  KittiGroundTruthSequence gt = exact;
  gt.objects.clear();
  for (size_t k = 0; k < source_of.size(); ++k)
    for (const auto& [id, source] : source_of[k]) {
      const auto o = exact.objects.find(source);
      if (o == exact.objects.end()) continue;
      const auto pose = o->second.T_camera_object.find(static_cast<int>(k));
      if (pose == o->second.T_camera_object.end()) continue;
      auto [it, added] = gt.objects.try_emplace(id, o->second);
      if (added) it->second.object_id = id, it->second.T_camera_object.clear();
      it->second.T_camera_object[static_cast<int>(k)] = pose->second;
    }
  return gt;
}

struct SettingResult {
  Setting setting;
  MethodOutcomes outcomes;
  std::optional<double> miou, detection_rate;  // degraded masks only
  double seconds = 0.0;
};

// study.csv: one row per setting and method, rewritten whole after each setting (a study cut short keeps
// the settings it finished).
void WriteStudyCsv(const std::string& path, const std::vector<SettingResult>& results) {
  WholeFile csv(path);
  csv << "component,setting,method,rte_pct,rre_deg_per_m,ate_m,omte_pct,omre_deg_per_m,omse_pct,object_coverage,"
         "object_pairs_estimated,object_gt_pairs,mask_miou,mask_detection_rate\n";
  for (const SettingResult& r : results)
    for (const auto& [method, outcome] : r.outcomes) {
      const MethodMetrics& m = outcome.metrics;
      csv << r.setting.component << ',' << r.setting.name << ',' << ToString(method) << ',' << Cell(m.camera.rte_pct)
          << ',' << Cell(m.camera.rre_deg_per_m) << ',' << Cell(m.camera.ate_m) << ',';
      if (m.objects)
        csv << Cell(m.objects->omte_pct) << ',' << Cell(m.objects->omre_deg_per_m) << ',' << Cell(m.objects->omse_pct)
            << ',' << Cell(m.objects->object_coverage) << ',' << m.objects->estimated_pairs << ',' << m.objects->gt_pairs;
      else
        csv << ",,,,,";
      csv << ',' << Cell(r.miou) << ',' << Cell(r.detection_rate) << '\n';
    }
  csv.commit();
}

void WriteTrackingCsv(const std::string& path, const std::vector<TrackingScore>& tracking) {
  WholeFile csv(path);
  csv << "tracker,frame_pairs,matches,object_matches,good_matches,mean_epe_px,mean_good_epe_px\n";
  for (const TrackingScore& t : tracking)
    csv << t.tracker << ',' << t.frame_pairs << ',' << Cell(t.matches) << ',' << Cell(t.object_matches) << ','
        << Cell(t.good_matches) << ',' << Cell(t.mean_epe_px) << ',' << Cell(t.mean_good_epe_px) << '\n';
  csv.commit();
}

}  // namespace

int RunStudyCommand(const StudyCommandOptions& options, std::ostream& out, std::ostream& err) {
  std::vector<SettingResult> results;
  std::vector<TrackingScore> tracking;
  try {
    const auto start = std::chrono::steady_clock::now();
    if (options.frames < 0) throw std::invalid_argument("--frames must be >= 0");
    const RunConfig base = BuildRunConfig(options, EntryPoint::kStudy);
    RequireWritableOutDir(options.out_dir);
    namespace fs = std::filesystem;
    const fs::path dir(options.dataset_dir);
    if (!fs::is_directory(dir / "image_1") || !fs::is_directory(dir / "flow"))
      throw std::invalid_argument(options.dataset_dir + " lacks " +
                                  (fs::is_directory(dir / "image_1") ? "flow/" : "image_1/") +
                                  ": the study needs a scene rendered with `dslam render-scene --stereo --exact-flow`");
    ImageDatasetOptions exact_options = base.dataset;
    exact_options.depth_encoding = "depth_mm";
    const ImageDataset exact(options.dataset_dir, exact_options);
    if (!exact.groundTruth() || !exact.hasMasks())
      throw std::invalid_argument(options.dataset_dir + " has no ground truth or no masks: the study compares with them");
    const int frames = options.frames > 0 ? std::min(options.frames, exact.size()) : exact.size();
    if (frames < 3) throw std::invalid_argument("the study needs at least 3 frames");
    if (!options.quiet)
      out << "Study of " << options.dataset_dir << ": " << frames << " frames, " << Settings().size()
          << " settings, each with ours, static-only and SLAM+MOT" << std::endl;

    // The degraded segmenter once over the exact masks: its ids per frame, and how good it is. The runs
    // replay it (same seed, frames in order) as they read the frames.
    MaskDegraderParams degrader_params;
    degrader_params.seed = options.seed;
    std::vector<std::map<int, int>> source_of;
    SegmentationScore segmentation;
    {
      MaskDegrader degrader(degrader_params);
      const int min_area = static_cast<int>(base.frontend.min_mask_area_pct / 100.0 * exact.camera().width *
                                            exact.camera().height);
      ImageDatasetOptions masks_only = exact_options;
      masks_only.read_flow = false;
      const ImageDataset data(options.dataset_dir, masks_only);
      for (int k = 0; k < frames; ++k) {
        const cv::Mat ids = data.read(k).instance_ids;
        const DegradedMaskFrame d = degrader.degrade(k, ids);
        segmentation.add(ids, d.ids, std::max(1, min_area));
        source_of.push_back(d.source_of);
      }
    }

    out << "Degraded segmenter: mIoU " << std::setprecision(3) << segmentation.miou() << ", detection rate "
        << segmentation.detectionRate() << " over " << segmentation.instances << " object instances" << std::endl;

    // The tracking comparison over consecutive frames, against the exact correspondences.
    if (!options.quiet) out << "Tracking comparison (LK, DIS, ORB against the exact flow) ..." << std::endl;
    {
      TrackingComparison comparison({FlowMethod::kLucasKanade, FlowMethod::kDis, FlowMethod::kOrb});
      ImageFrame previous = exact.read(0);
      for (int k = 1; k < frames; ++k) {
        ImageFrame current = exact.read(k);
        comparison.add(previous, current);
        previous = std::move(current);
      }
      tracking = comparison.scores();
    }
    WriteTrackingCsv(options.out_dir + "/tracking.csv", tracking);

    for (const Setting& setting : Settings()) {
      const auto t0 = std::chrono::steady_clock::now();
      if (!options.quiet) out << "  " << setting.component << ": " << setting.name << " ..." << std::flush;
      RunConfig config = base;
      config.frontend.flow.method = setting.tracking;
      ImageDatasetOptions data_options = base.dataset;
      data_options.depth_encoding = setting.stereo ? "stereo" : "depth_mm";
      data_options.read_flow = setting.tracking == FlowMethod::kPrecomputed;
      ImageDataset data(options.dataset_dir, data_options);
      auto degrader = std::make_shared<MaskDegrader>(degrader_params);
      const double sigma = setting.depth_sigma_m;
      const uint64_t seed = options.seed;
      const bool degraded = setting.degraded_masks;
      data.setFrameTransform([degrader, sigma, seed, degraded](ImageFrame& f) {
        if (sigma > 0.0) {
          // The paper's 3D point noise, on every depth the sensor gives: seeded per frame.
          cv::Mat noise(f.depth_m.size(), CV_32F);
          cv::RNG rng(seed * 7919ULL + static_cast<uint64_t>(f.frame_index) + 1);
          rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
          cv::Mat valid = f.depth_m > 0.0f;
          cv::Mat noisy = f.depth_m + noise;
          noisy.copyTo(f.depth_m, valid);
          f.depth_m.setTo(0.0f, f.depth_m < 0.0f);
        }
        if (degraded) f.instance_ids = degrader->degrade(f.frame_index, f.instance_ids).ids;
      });
      if (degraded) data.setGroundTruth(GroundTruthWithDegradedIds(*exact.groundTruth(), source_of));
      ImageRunOptions run;
      run.max_frames = frames;
      SettingResult r;
      r.setting = setting;
      r.outcomes = RunImageStreamed(data, config, run).outcomes;
      if (degraded) r.miou = segmentation.miou(), r.detection_rate = segmentation.detectionRate();
      r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (!options.quiet) {
        const auto& m = r.outcomes.at(Method::kOurs).metrics;
        const std::string omse = m.objects ? Cell(m.objects->omse_pct) : "";
        out << " RTE " << Cell(m.camera.rte_pct) << " %, OMSE "
            << (omse.empty() ? std::string("- (no moving object)") : omse + " %") << " (" << std::setprecision(3)
            << r.seconds << " s)" << std::endl;
      }
      results.push_back(std::move(r));
      WriteStudyCsv(options.out_dir + "/study.csv", results);
    }

    out << "Study written to " << options.out_dir << "/study.csv and tracking.csv ("
        << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s)" << std::endl;
  } catch (const std::exception& e) {
    err << "dslam study: error: " << e.what() << std::endl;
    return 2;
  }
  // The page a person reads: both tables, and the figures when drawn.
  auto write_report = [&](const std::vector<std::string>& figures) {
    auto rows = [](const CsvTable& t) {
      std::vector<std::vector<std::string>> all = {t.header};
      all.insert(all.end(), t.rows.begin(), t.rows.end());
      return all;
    };
    WriteStudyReportHtml(options.dataset_dir, rows(ReadCsv(options.out_dir + "/study.csv")),
                         rows(ReadCsv(options.out_dir + "/tracking.csv")), figures, options.out_dir + "/report.html");
  };
  if (options.no_figures) {
    try {
      write_report({});
    } catch (const std::exception& e) {
      err << "dslam study: error: " << e.what() << std::endl;
      return 2;
    }
    return 0;
  }

  std::string error;
  const auto display = HeadlessDisplay::Acquire(&error);
  if (!display) {
    err << "dslam study: error: " << error << std::endl;
    return 3;
  }
  try {
    FigureOptions figure;
    figure.scale = options.figure_scale;
    figure.height = 1400;
    std::vector<std::string> settings;
    for (const SettingResult& r : results) settings.push_back(r.setting.name);
    auto panel = [&](const std::string& title, const std::string& y, Method baseline, auto metric) {
      BarPanel p{title, y, {"ours", ToString(baseline)}, {}};
      for (const SettingResult& r : results) {
        std::vector<double> row;
        for (Method m : {Method::kOurs, baseline})
          row.push_back(r.outcomes.count(m) ? metric(r.outcomes.at(m).metrics) : std::numeric_limits<double>::quiet_NaN());
        p.values.push_back(row);
      }
      return p;
    };
    const std::vector<BarPanel> effects = {
        panel("Camera: relative translation error", "RTE (%)", Method::kStaticOnly,
              [](const MethodMetrics& m) { return Value(m.camera.rte_pct); }),
        panel("Camera: relative rotation error", "RRE (deg/m)", Method::kStaticOnly,
              [](const MethodMetrics& m) { return Value(m.camera.rre_deg_per_m); }),
        panel("Objects: motion translation error", "OMTE (%)", Method::kSlamMot,
              [](const MethodMetrics& m) { return m.objects ? Value(m.objects->omte_pct) : NAN; }),
        panel("Objects: motion rotation error", "OMRE (deg/m)", Method::kSlamMot,
              [](const MethodMetrics& m) { return m.objects ? Value(m.objects->omre_deg_per_m) : NAN; }),
        panel("Objects: speed error", "OMSE (%)", Method::kSlamMot,
              [](const MethodMetrics& m) { return m.objects ? Value(m.objects->omse_pct) : NAN; })};
    DrawBarFigure("Effect of each front-end component (one made realistic at a time, the others exact)", settings,
                  effects, options.out_dir + "/study_effects.png", figure);
    std::vector<std::string> trackers;
    BarPanel matches{"Matches per frame pair", "matches", {"all", "on objects", "good (EPE < 3 px)"}, {}};
    BarPanel epe{"End-point error against the exact correspondences", "EPE (px)", {"all matches", "good matches"}, {}};
    for (const TrackingScore& t : tracking) {
      trackers.push_back(t.tracker);
      matches.values.push_back({t.matches, t.object_matches, t.good_matches});
      epe.values.push_back({t.mean_epe_px, t.mean_good_epe_px});
    }
    figure.height = 1000;
    DrawBarFigure("Flow vs matching: correspondences from frame k to k+1", trackers, {matches, epe},
                  options.out_dir + "/study_tracking.png", figure);
    write_report({"study_effects.png", "study_tracking.png"});
    out << "Figures: " << options.out_dir << "/study_effects.png, " << options.out_dir
        << "/study_tracking.png; the page: " << options.out_dir << "/report.html" << std::endl;
  } catch (const std::exception& e) {
    err << "dslam study: error: " << e.what() << std::endl;
    return 2;
  }
  return 0;
}

}  // namespace dslam
