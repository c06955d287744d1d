#pragma once
// `dslam study`: the paper's front-end study on a rendered scene with exact ground truth. Starting from
// exact inputs (rendered depth, exact masks, exact correspondences), one front-end component at a time is
// made realistic: depth (Gaussian noise of 0.02, 0.04, 0.06 m, or stereo SGBM), segmentation (a degraded
// segmenter, data/mask_degrader.h) or tracking (LK, DIS, ORB matching); a last run makes all three
// realistic together. Each setting runs ours and the baselines; the study writes study.csv, the tracking
// comparison tracking.csv, two figures and report.html.

#include <ostream>
#include <string>

#include "app/run_setup.h"

namespace dslam {

struct StudyCommandOptions : CommonRunOptions {
  StudyCommandOptions() {
    out_dir = "results/study";
    sigma_given = false;  // the configuration file's point sigma, else the default
  }
  std::string dataset_dir;  // rendered with `render-scene --stereo --exact-flow`
  int frames = 100;         // 0: all
};

// Exit codes: 0 done, 2 bad input (a dataset without the stereo pair or the exact flow among them),
// 3 no display for the figures.
int RunStudyCommand(const StudyCommandOptions& options, std::ostream& out, std::ostream& err);

}  // namespace dslam
