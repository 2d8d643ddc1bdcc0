#!/usr/bin/env python3
"""The Slurm helpers of scripts/slurm/ without Slurm: each script runs under bash with the
environment an array task would have (SLURM_ARRAY_TASK_ID, _COUNT, _MIN, _MAX), a fake `veil`
that records its arguments and, for submit-regress.sh, a fake `sbatch` on PATH. Checks

  - the frame slices of render-frames.sbatch: an array's tasks cover the range exactly once,
    --array=1-8 renders the same slices as --array=0-7, a re-submitted task (VEIL_SHARDS=N,
    --array=K) renders the same frames as task K of the first array, and a task past the slices
    is refused naming the range;
  - every numeric input (VEIL_SHARDS, SLURM_ARRAY_TASK_*, FRAMES, --tasks, --cpus) is matched as
    a plain decimal integer in range and never evaluated: a command substitution in it creates
    no file, 20-digit numbers are refused rather than wrapped, --tasks 1000000000 is refused at
    once;
  - bad input ends in one line of the script's own (not bash's "parameter null or not set"),
    exit status 2, and veil / sbatch not run;
  - VEIL_RENDER_ARGS keeps one argument per line (spaces inside an argument kept).

Standard library only. Usage: slurm_scripts.py [REPO_ROOT]
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                       os.path.join(os.path.dirname(__file__), "..", ".."))
SLURM = os.path.join(ROOT, "scripts", "slurm")
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


work = tempfile.mkdtemp(prefix="veil-slurm-scripts.")
bindir = os.path.join(work, "bin")
os.makedirs(bindir)
record = os.path.join(work, "record")
# The fakes write their arguments, NUL-separated, to $RECORD (one file per call, appended).
for name in ("veil", "sbatch"):
    with open(os.path.join(bindir, name), "w") as f:
        f.write('#!/bin/bash\n{ printf "%s\\0" "$(basename "$0")" "$@"; printf "\\n"; } >>"$RECORD"\n'
                + ('echo 4242\n' if name == "sbatch" else ""))
    os.chmod(os.path.join(bindir, name), 0o755)


def run(script, env=(), args=()):
    """Runs scripts/slurm/SCRIPT in a fresh folder; returns (status, stdout, stderr, calls)."""
    cwd = tempfile.mkdtemp(dir=work)
    if os.path.exists(record):
        os.remove(record)
    e = {"PATH": bindir + ":/usr/bin:/bin", "HOME": cwd, "RECORD": record,
         "VEIL": os.path.join(bindir, "veil")}
    e.update(dict(env))
    try:
        p = subprocess.run(["bash", os.path.join(SLURM, script), *args], cwd=cwd, env=e,
                           capture_output=True, text=True, timeout=20)
    except subprocess.TimeoutExpired:
        p = subprocess.CompletedProcess([], -1, "", f"{script}: ran past 20 s")
    calls = []
    if os.path.exists(record):
        with open(record) as f:
            calls = [line.rstrip("\0").split("\0") for line in f.read().splitlines() if line]
    return p.returncode, p.stdout, p.stderr, calls, cwd


def frames_of(call):
    """The frame list of a recorded `veil render ... --frames A-B:S` call."""
    m = re.fullmatch(r"(-?\d+)-(-?\d+):(\d+)", call[call.index("--frames") + 1])
    return list(range(int(m[1]), int(m[2]) + 1, int(m[3])))


def refused(script, env, words, what, args=()):
    """SCRIPT with ENV exits 2 with one line of its own holding every word, runs nothing."""
    rc, out, err, calls, cwd = run(script, env, args)
    lines = err.strip().splitlines()
    ok = (rc == 2 and len(lines) == 1 and not calls and all(w in lines[0] for w in words)
          and "not set" not in err and "syntax error" not in err and not re.search(r"line \d+:", err)
          and not os.path.exists(os.path.join(cwd, "PWNED")))
    check(ok, f"{script}: {what} -> exit 2, one line naming {words}"
              + ("" if ok else f" (got {rc}, calls {calls}, stderr {err.strip()!r})"))
    return lines[0] if lines else ""


FRAME_ENV = {"SCENE": "anim.json", "PATTERN": "f.####.exr"}


def array_task(first_id, count, task_id, **more):
    env = dict(FRAME_ENV, SLURM_ARRAY_TASK_MIN=str(first_id),
               SLURM_ARRAY_TASK_MAX=str(first_id + count - 1),
               SLURM_ARRAY_TASK_COUNT=str(count), SLURM_ARRAY_TASK_ID=str(task_id))
    env.update(more)
    return env


# --- render-frames.sbatch: slices -------------------------------------------------------------
def slices(first_id, frames, n):
    got = []
    for i in range(first_id, first_id + n):
        rc, out, err, calls, _ = run("render-frames.sbatch", array_task(first_id, n, i, FRAMES=frames))
        if rc != 0 or len(calls) != 1:
            check(False, f"render-frames task {i} of {first_id}-{first_id + n - 1}: {rc} {err}")
            return None
        got.append(frames_of(calls[0]))
    return got


s0 = slices(0, "0-239", 8)
check(s0 is not None and sum(s0, []) == list(range(240)),
      "render-frames --array=0-7, FRAMES=0-239: the slices cover 0..239 once, in order")
s1 = slices(1, "0-239", 8)
check(s1 == s0, "render-frames --array=1-8 renders the same slices as --array=0-7")
s2 = slices(0, "-7-30:4", 3)
check(s2 is not None and sum(s2, []) == list(range(-7, 31, 4)),
      "render-frames FRAMES=-7-30:4 as 3 tasks: every 4th frame from -7, once")

# Re-submission of task 3 alone, as docs/cluster.md says: VEIL_SHARDS=8 sbatch --array=3.
rc, out, err, calls, _ = run("render-frames.sbatch", array_task(3, 1, 3, FRAMES="0-239", VEIL_SHARDS="8"))
check(rc == 0 and len(calls) == 1 and s0 is not None and frames_of(calls[0]) == s0[3],
      "render-frames: VEIL_SHARDS=8 --array=3 renders task 3's frames of the first array (90-119)")
check(calls and calls[0][:3] == ["veil", "render", "anim.json"] and "--resume" in calls[0],
      "render-frames: veil render SCENE --frames ... -o PATTERN --resume")

refused("render-frames.sbatch", array_task(3, 1, 3, FRAMES="0-239"), ["task 3", "VEIL_SHARDS"],
        "--array=3 alone without VEIL_SHARDS")
refused("render-frames.sbatch",
        dict(FRAME_ENV, FRAMES="0-239", SLURM_ARRAY_TASK_COUNT="1", SLURM_ARRAY_TASK_ID="3"),
        ["task 3", "VEIL_SHARDS"], "COUNT=1 ID=3 (no MIN/MAX): the issue's re-submission")
refused("render-frames.sbatch", array_task(0, 1, 8, FRAMES="0-239", VEIL_SHARDS="8"),
        ["task 8", "0-7"], "VEIL_SHARDS=8 task 8: past the slices")
refused("render-frames.sbatch",
        dict(FRAME_ENV, FRAMES="0-239", SLURM_ARRAY_TASK_MIN="0", SLURM_ARRAY_TASK_MAX="4",
             SLURM_ARRAY_TASK_COUNT="3", SLURM_ARRAY_TASK_ID="2"),
        ["0-4", "VEIL_SHARDS"], "--array=0,2,4 (not contiguous)")

# --- every numeric input: injection, huge numbers, not numbers ---------------------------------
inject = "HOME[$(touch PWNED)]+1"
for var in ("VEIL_SHARDS", "SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_MIN",
            "SLURM_ARRAY_TASK_MAX"):
    for value in (inject, "99999999999999999999", "0x10", "1e3", " 3", ""):
        env = array_task(0, 8, 1, FRAMES="0-239")
        if value == "" and var in ("VEIL_SHARDS", "SLURM_ARRAY_TASK_MIN", "SLURM_ARRAY_TASK_MAX"):
            continue  # empty means unset: the default applies
        env[var] = value
        for script in ("render-frames.sbatch", "regress.sbatch"):
            if script == "regress.sbatch":
                env = dict(env, SUITE="suite.json", OUT="out")
            refused(script, env, [var] if value else [], f"{var}={value!r}")
for frames in ("0-$(touch PWNED)", "0-99999999999999999999", "99999999999999999999-1",
               "1-99999999999999999999", "0-10:0", "0-10:99999999999999999999", "10-0", "a-b", ""):
    refused("render-frames.sbatch", array_task(0, 2, 0, FRAMES=frames), ["FRAMES"],
            f"FRAMES={frames!r}")
for missing in ("SCENE", "PATTERN"):
    env = array_task(0, 2, 0, FRAMES="0-9")
    del env[missing]
    refused("render-frames.sbatch", env, [missing], f"{missing} unset")
refused("render-frames.sbatch", dict(FRAME_ENV, FRAMES="0-9"), ["array"], "not an array task")

# --- VEIL_RENDER_ARGS and the script's arguments: one argument each ---------------------------
rc, out, err, calls, _ = run("render-frames.sbatch",
                             array_task(0, 1, 0, FRAMES="0-3",
                                        VEIL_RENDER_ARGS="--width\n64\n--set\nlabel=a b\n"),
                             args=["--height", "36", "--set", "name=x y"])
check(rc == 0 and calls and calls[0][-8:] == ["--height", "36", "--set", "name=x y", "--width", "64",
                                             "--set", "label=a b"],
      f"render-frames: script arguments and VEIL_RENDER_ARGS lines each one argument ({calls})")
refused("render-frames.sbatch",
        array_task(0, 1, 0, FRAMES="0-3", VEIL_RENDER_ARGS="--width 64 --height 48"),
        ["VEIL_RENDER_ARGS", "one per line"], "VEIL_RENDER_ARGS split by spaces")

# --- regress.sbatch: shards --------------------------------------------------------------------
REG = {"SUITE": "suite.json", "OUT": "out"}
rc, out, err, calls, _ = run("regress.sbatch", array_task(1, 4, 3, **REG))
check(rc == 0 and calls and calls[0][calls[0].index("--shard") + 1] == "2/4"
      and calls[0][calls[0].index("-o") + 1] == "out/shard-2",
      "regress.sbatch --array=1-4 task 3 runs shard 2/4 into out/shard-2")
rc, out, err, calls, _ = run("regress.sbatch", array_task(2, 1, 2, VEIL_SHARDS="4", **REG))
check(rc == 0 and calls and calls[0][calls[0].index("--shard") + 1] == "2/4",
      "regress.sbatch VEIL_SHARDS=4 --array=2 (re-submission) runs shard 2/4")
refused("regress.sbatch", array_task(0, 1, 4, VEIL_SHARDS="4", **REG), ["task 4", "0-3"],
        "VEIL_SHARDS=4 task 4")
refused("regress.sbatch", array_task(0, 2, 0, SUITE="s.json"), ["OUT"], "OUT unset")

# --- regress-merge.sbatch ----------------------------------------------------------------------
rc, out, err, calls, _ = run("regress-merge.sbatch", dict(REG, VEIL_SHARDS="3"))
check(rc == 0 and calls and calls[0][calls[0].index("--merge") + 1:][:3]
      == ["out/shard-0", "out/shard-1", "out/shard-2"],
      "regress-merge.sbatch VEIL_SHARDS=3 merges shard-0..2")
for value in (inject, "99999999999999999999", "0", "-1", "2+2"):
    refused("regress-merge.sbatch", dict(REG, VEIL_SHARDS=value), ["VEIL_SHARDS"],
            f"VEIL_SHARDS={value!r}")
refused("regress-merge.sbatch", {"OUT": "out", "VEIL_SHARDS": "2"}, ["SUITE"], "SUITE unset")

# --- submit-regress.sh -------------------------------------------------------------------------
suite = os.path.join(work, "suite.json")
open(suite, "w").write("{}")
out_dir = os.path.join(work, "sub")
os.makedirs(os.path.join(out_dir, "shard-1"))
open(os.path.join(out_dir, "shard-1", "results.json"), "w").write("{}")
rc, out, err, calls, _ = run("submit-regress.sh", args=["--tasks", "3", "--resume", suite, out_dir])
arrays = [c for c in calls if any(a.startswith("--array=") for a in c)]
check(rc == 0 and len(calls) == 2 and arrays and "--array=0,2" in arrays[0],
      f"submit-regress --tasks 3 --resume submits tasks 0,2 and the merge ({out.strip()!r})")
for value in ("1000000000", "99999999999999999999", inject, "0", "-3", "4x"):
    refused("submit-regress.sh", {}, ["--tasks"], f"--tasks {value}",
            args=["--tasks", value, suite, out_dir])
refused("submit-regress.sh", {}, ["--tasks", "value"], "--tasks without a value",
        args=[suite, out_dir, "--tasks"])
refused("submit-regress.sh", {}, ["--cpus"], "--cpus 99999999999999999999",
        args=["--cpus", "99999999999999999999", suite, out_dir])

shutil.rmtree(work, ignore_errors=True)
if failures:
    print(f"{len(failures)} check(s) failed", file=sys.stderr)
    sys.exit(1)
print("all checks passed")
