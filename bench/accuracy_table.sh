#!/usr/bin/env bash
# Accuracy of ours (and the window against batch) on every acceptance scene, as one table:
# scene, schedule, RTE %, ATE m, OMTE %, OMSE %. Used to show that a back-end change trades no accuracy.
# Usage: bench/accuracy_table.sh DSLAM_BINARY OUT_DIR [CONFIG.yaml]
#   (reads ../shared/data; renders scenes into OUT_DIR; CONFIG, when given, goes to every run as --config)
set -euo pipefail
dslam="$1"
out="$2"
config=()
[ -n "${3:-}" ] && config=(--config "$3")
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
kitti="$root/../shared/data/kitti_tracking"
mkdir -p "$out"
row() {  # scene schedule metrics.json
  jq -r --arg s "$1" --arg w "$2" '.methods.ours | [$s, $w, .rte_pct, .ate_m, .omte_pct, .omse_pct] | map(tostring) | join(" | ")' "$3" |
    sed 's/^/| /; s/$/ |/'
}
echo "| scene | schedule | RTE % | ATE m | OMTE % | OMSE % |"
echo "|---|---|---|---|---|---|"
for sched in window:10 batch; do
  tag="${sched/:/}"
  "$dslam" sim --scenario paper --schedule "$sched" "${config[@]}" --out "$out/paper_$tag" --quiet --no-figures >/dev/null
  row "sim paper" "$sched" "$out/paper_$tag/metrics.json"
  "$dslam" sim --scenario city --schedule "$sched" "${config[@]}" --out "$out/city_$tag" --quiet --no-figures >/dev/null
  row "sim city" "$sched" "$out/city_$tag/metrics.json"
  if [ -d "$kitti" ]; then
    for seq in 0000 0003 0005; do
      "$dslam" kitti-replay --data "$kitti" --seq "$seq" --schedule "$sched" "${config[@]}" --out "$out/replay_${seq}_$tag" --quiet --no-figures >/dev/null
      row "KITTI replay $seq" "$sched" "$out/replay_${seq}_$tag/metrics.json"
    done
  fi
done
scenes=(demo)
[ -d "$out/scene_demo" ] || "$dslam" render-scene --scenario city --frames 60 --out "$out/scene_demo" --quiet >/dev/null
if [ -d "$kitti" ]; then
  for seq in 0000 0003 0005; do
    [ -d "$out/scene_$seq" ] || "$dslam" render-scene --kitti "$kitti" --seq "$seq" --out "$out/scene_$seq" --quiet >/dev/null
    scenes+=("$seq")
  done
fi
for sched in window:10 batch; do
  tag="${sched/:/}"
  for s in "${scenes[@]}"; do
    "$dslam" run --dataset "$out/scene_$s" --methods ours --schedule "$sched" "${config[@]}" --category VEHICLE --out "$out/run_${s}_$tag" --quiet --no-figures >/dev/null
    row "rendered $s" "$sched" "$out/run_${s}_$tag/metrics.json"
  done
done
