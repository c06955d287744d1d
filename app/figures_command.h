#pragma once

#include <ostream>
#include <string>

#include "render/figures.h"

namespace dslam {

// `dslam figures RESULTS_DIR`: trajectory.png, speeds.png, errors.png, map.png and report.html from
// a run's result files. Starts (and stops) its own Xvfb when DISPLAY is unset.
// Exit codes: 0 done, 2 unreadable results or unwritable figures, 3 no display to be had.
int RunFiguresCommand(const std::string& results_dir, const FigureOptions& options, std::ostream& out,
                      std::ostream& err);

}  // namespace dslam
