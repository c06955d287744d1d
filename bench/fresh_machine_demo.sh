#!/usr/bin/env bash
# Times scripts/demo.sh on a fresh Debian 12: a minimal bookworm made by debootstrap (apt's lists and cache
# empty, none of scripts/deps.txt installed, no compiler cache), this repository cloned into it, and the demo
# run as root inside it (chroot), as a new user runs it after cloning. Prints the whole time and its parts
# (package installs, build, render and run). Needs root and debootstrap; downloads the packages from MIRROR.
# Usage: bench/fresh_machine_demo.sh [WORK_DIR (default /tmp/dslam_fresh_machine)] [MIRROR (default deb.debian.org)]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="${1:-/tmp/dslam_fresh_machine}"
mirror="${2:-http://deb.debian.org/debian}"
[ "$(id -u)" -eq 0 ] || { echo "fresh_machine_demo: needs root (debootstrap, chroot, mount)" >&2; exit 2; }
command -v debootstrap >/dev/null || { echo "fresh_machine_demo: needs debootstrap (apt-get install debootstrap)" >&2; exit 2; }
[ ! -e "$work" ] || { echo "fresh_machine_demo: $work exists: give a folder that does not" >&2; exit 2; }
mkdir -p "$work"
sys="$work/system"
mounted=()
cleanup() {  # slave mounts first: unmounting them must not reach the host's /dev and /sys
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do umount -R "${mounted[i]}" 2>/dev/null || umount -l "${mounted[i]}" || true; done
}
trap cleanup EXIT
echo "fresh_machine_demo: debootstrap bookworm (minbase) into $sys"
debootstrap --variant=minbase bookworm "$sys" "$mirror" > "$work/debootstrap.log" 2>&1
git clone -q "$root" "$sys/root/dslam"
mount -t proc proc "$sys/proc" && mounted+=("$sys/proc")
for m in sys dev; do
  mount --rbind "/$m" "$sys/$m" && mount --make-rslave "$sys/$m" && mounted+=("$sys/$m")
done
cp /etc/resolv.conf "$sys/etc/resolv.conf"
echo "fresh_machine_demo: scripts/demo.sh inside (log: $work/demo.log)"
start=$(date +%s.%N)
status=0
chroot "$sys" /bin/bash -c 'cd /root/dslam && bash scripts/demo.sh' > "$work/demo.log" 2>&1 || status=$?
end=$(date +%s.%N)
[ "$status" -eq 0 ] || { echo "fresh_machine_demo: scripts/demo.sh failed (status $status), see $work/demo.log" >&2; exit 1; }
at() { stat -c %.Y "$1"; }  # when a file was last written
configured=$(at "$sys/root/dslam/build/CMakeCache.txt")
built=$(at "$sys/root/dslam/build/dslam")
awk -v s="$start" -v c="$configured" -v b="$built" -v e="$end" -v n="$(grep -c '^Setting up' "$work/demo.log")" 'BEGIN {
  printf "scripts/demo.sh on a fresh Debian 12: %.0f s (%d min %02d s): packages (%d) %.0f s, configure and build dslam %.0f s, render and run %.0f s\n",
         e - s, int((e - s) / 60), int(e - s) % 60, n, c - s, b - c, e - b }'
