#!/usr/bin/env bash
# Installs the Debian packages listed in scripts/deps.txt when missing, then configures and builds.
# Usage: scripts/setup.sh [--target TARGET]... [BUILD_DIR]   (default: everything into build/; Release; -j2)
#   --target TARGET   build only TARGET (and what it needs), e.g. dslam; may be repeated
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
targets=()
build_dir="$root/build"
while [ $# -gt 0 ]; do
  case "$1" in
    --target) [ $# -ge 2 ] || { echo "setup: --target needs a target name" >&2; exit 2; }
              targets+=(--target "$2"); shift 2 ;;
    -*) echo "setup: unknown option $1 (usage: scripts/setup.sh [--target TARGET]... [BUILD_DIR])" >&2; exit 2 ;;
    *) build_dir="$1"; shift ;;
  esac
done

mapfile -t wanted < <(grep -vE '^\s*(#|$)' "$root/scripts/deps.txt")
missing=()
for pkg in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing missing Debian packages: ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# Ninja (scripts/deps.txt) compiles every layer's files in parallel where make waits for each library in turn;
# a build folder keeps the generator it was first configured with.
generator=()
if [ ! -f "$build_dir/CMakeCache.txt" ] && command -v ninja >/dev/null; then generator=(-G Ninja); fi
cmake -S "$root" -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j2 "${targets[@]}"
