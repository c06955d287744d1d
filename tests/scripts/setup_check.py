#!/usr/bin/env python3
"""scripts/setup.sh picks its Debian packages from scripts/deps.txt: every one for the tests, and for the demo
(--dslam-only) only those above the marker line, so that a fresh machine installs no test-only package to run
the demo. Usage: setup_check.py REPOSITORY_ROOT"""
import subprocess
import sys
from pathlib import Path

root = Path(sys.argv[1])
setup = root / "scripts" / "setup.sh"


def packages(*options):
    out = subprocess.run(["bash", str(setup), *options, "--list-packages"], check=True, capture_output=True, text=True)
    return out.stdout.split()


everything = packages()
dslam_only = packages("--dslam-only")
lines = (root / "scripts" / "deps.txt").read_text().splitlines()
marker = next(i for i, line in enumerate(lines) if line.startswith("# -- tests"))
above = [l.strip() for l in lines[:marker] if l.strip() and not l.startswith("#")]
below = [l.strip() for l in lines[marker:] if l.strip() and not l.startswith("#")]

failures = []
if everything != above + below:
    failures.append(f"the full set is not every package of deps.txt: {everything}")
if dslam_only != above:
    failures.append(f"--dslam-only is not the part above the marker: {dslam_only}")
for needed in ("libceres-dev", "libfastrtps-dev", "fastddsgen", "libvtk9-dev", "libpcl-dev", "libopencv-dev"):
    if needed not in dslam_only:
        failures.append(f"dslam needs {needed}, --dslam-only leaves it out")
for test_only in ("libgtest-dev", "cyclonedds-dev"):
    if test_only in dslam_only or test_only not in everything:
        failures.append(f"{test_only} belongs to the tests' part only")
bad = subprocess.run(["bash", str(setup), "--no-such-option"], capture_output=True, text=True)
if bad.returncode != 2 or "unknown option --no-such-option" not in bad.stderr:
    failures.append(f"an unknown option gave exit {bad.returncode}: {bad.stderr.strip()}")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
