#!/usr/bin/env bash
# Builds everything and runs the test suite (CI runs it whole).
# Usage: scripts/test.sh [--unit | --label LABEL] [extra ctest options]
#   (none)         every test: labels unit, acceptance, dds, interop, network
#   --unit         the unit tests alone (about a minute and a half on two cores once built)
#   --label LABEL  the tests of one label (unit, acceptance, dds, interop, network)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
select=()
case "${1:-}" in
  --unit) select=(-L '^unit$'); shift ;;
  --label)
    [ $# -ge 2 ] || { echo "test.sh: --label needs one of unit, acceptance, dds, interop, network" >&2; exit 2; }
    case "$2" in unit|acceptance|dds|interop|network) ;; *)
      echo "test.sh: unknown label '$2' (one of unit, acceptance, dds, interop, network)" >&2; exit 2 ;;
    esac
    select=(-L "^$2\$"); shift 2 ;;
esac
"$root/scripts/setup.sh"
cd "$root/build"
ctest --output-on-failure -j2 "${select[@]}" "$@"
