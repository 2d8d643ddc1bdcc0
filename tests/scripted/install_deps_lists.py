#!/usr/bin/env python3
"""scripts/install-deps.sh's package lists: the default one (`make run`) holds what building
and rendering need and none of the test-only packages (Slurm, munge, Chromium, Xvfb, pytest,
Matplotlib); `--test` (`make test`, CI) adds them; an unknown option is a usage error (exit 2,
one line). Installs nothing (`--list`). Usage: install_deps_lists.py [REPO_ROOT]"""
import os
import subprocess
import sys

root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                       os.path.join(os.path.dirname(__file__), "..", ".."))
script = os.path.join(root, "scripts", "install-deps.sh")
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def run(*args):
    return subprocess.run(["bash", script, *args], capture_output=True, text=True, timeout=30)


default = run("--list")
test = run("--list", "--test")
d, t = default.stdout.split(), test.stdout.split()
check(default.returncode == 0 and test.returncode == 0, "--list and --list --test exit 0")
test_only = ["munge", "slurmctld", "slurmd", "slurm-client", "chromium", "xvfb", "xauth",
             "python3-pytest", "python3-matplotlib"]
for p in test_only:
    check(p not in d, f"default list has no {p}")
    check(p in t, f"--test list has {p}")
for p in ["build-essential", "cmake", "ninja-build", "libopenvdb-dev", "libopenimageio-dev",
          "libepoxy-dev", "libegl-mesa0", "libgl1-mesa-dri", "pybind11-dev", "python3-numpy",
          "fonts-dejavu-core", "libgtest-dev"]:
    check(p in d, f"default list has {p} (the build or a render needs it)")
check(set(d) <= set(t) and len(set(d)) == len(d), "--test adds to the default list; no name twice")
bad = run("--bogus")
check(bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1
      and "--bogus" in bad.stderr, "an unknown option: exit 2, one line naming it")
if failures:
    sys.exit(f"{len(failures)} check(s) failed")
print("all checks passed")
