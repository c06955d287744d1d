#!/usr/bin/env bash
# The main job on the embedded default: the paper's simulated experiment, all three methods,
# results under results/paper/. Usage: scripts/demo.sh [extra dslam sim options]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
out="$root/results/paper"
"$root/build/dslam" sim --scenario paper --seed 1 --out "$out" "$@"
echo "Results: $out (metrics.json, camera_*.tum, object_motions.csv, object_speeds.csv)"
echo "Figures: $out/trajectory.png speeds.png errors.png map.png; open $out/report.html in a browser"
