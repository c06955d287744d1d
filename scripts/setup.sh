#!/usr/bin/env bash
# Installs the Debian packages listed in scripts/deps.txt when missing, then configures and builds.
# Usage: scripts/setup.sh [--dslam-only] [--list-packages] [--target TARGET]... [BUILD_DIR]
#   (default: every package, everything into build/; Release; -j2)
#   --dslam-only      only the packages dslam needs (deps.txt above its marker line) and only the dslam
#                     program: no tests, no benchmarks (what scripts/demo.sh runs)
#   --target TARGET   build only TARGET (and what it needs), e.g. dslam; may be repeated
#   --list-packages   print the Debian packages it would want (one per line) and exit
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
targets=()
build_dir="$root/build"
dslam_only=false
list_packages=false
while [ $# -gt 0 ]; do
  case "$1" in
    --dslam-only) dslam_only=true; shift ;;
    --list-packages) list_packages=true; shift ;;
    --target) [ $# -ge 2 ] || { echo "setup: --target needs a target name" >&2; exit 2; }
              targets+=(--target "$2"); shift 2 ;;
    -*) echo "setup: unknown option $1 (usage: scripts/setup.sh [--dslam-only] [--list-packages] [--target TARGET]... [BUILD_DIR])" >&2; exit 2 ;;
    *) build_dir="$1"; shift ;;
  esac
done
with_tests=ON
if $dslam_only; then
  with_tests=OFF
  targets=(--target dslam)
fi

if $dslam_only; then
  mapfile -t wanted < <(sed '/^# -- tests/,$d' "$root/scripts/deps.txt" | grep -vE '^\s*(#|$)')
else
  mapfile -t wanted < <(grep -vE '^\s*(#|$)' "$root/scripts/deps.txt")
fi
if $list_packages; then
  printf '%s\n' "${wanted[@]}"
  exit 0
fi
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
cmake -S "$root" -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DDSLAM_BUILD_TESTS=$with_tests -DDSLAM_BUILD_BENCHMARKS=$with_tests >/dev/null
cmake --build "$build_dir" -j2 "${targets[@]}"
