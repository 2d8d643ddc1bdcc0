#!/usr/bin/env python3
"""Runs named benchmark sets (bench/sets/NAME.json) and writes one JSON file per set and run.

    python3 bench/run.py frame-techniques [more sets or set files...] [--out DIR]

Each set declares groups of cases (scene, technique, size, warm-up and timed frames, options);
every case is one process of veil-bench (GL_TIME_ELAPSED per pass, medians after warm-up) or
veil-voxbench. Before the first case the driver renders throwaway frames for the set's
`clock_warmup_s` seconds (GPU clocks ramp up during the first seconds of a process tree).
Ratios compare each case with its group's baseline case measured in the same run.
The output schema is described in bench/README.md; bench/report.py turns the files into
RESULTS.md. Python 3 standard library only (it runs on the GPU machine too).
"""
import argparse
import datetime
import fnmatch
import json
import math
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
import report  # noqa: E402  (bench/report.py: the tables and the schema check)

SCHEMA = report.SCHEMA
QUICK = False  # --quick: every case at 64x36, one frame


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def find_tool(name, bin_dir):
    """The program from --bin, PATH, or the release build of this checkout."""
    candidates = []
    if bin_dir:
        candidates.append(os.path.join(bin_dir, name))
    found = shutil.which(name)
    if found:
        candidates.append(found)
    candidates.append(os.path.join(ROOT, "build", "release", "bench", name))
    for c in candidates:
        if os.path.isfile(c) and os.access(c, os.X_OK):
            return os.path.abspath(c)
    raise SystemExit(f"run.py: {name} not found (build it, pass --bin DIR, or source .gpu/env.sh)")


def load_set(arg):
    path = arg if arg.endswith(".json") else os.path.join(ROOT, "bench", "sets", arg + ".json")
    with open(path) as f:
        s = json.load(f)
    for key in ("name", "groups"):
        if key not in s:
            raise SystemExit(f"run.py: {path}: missing '{key}'")
    return path, s


def git_commit():
    """The commit the measured programs were built from: with the bundle's programs (.gpu/env.sh
    sourced), the commit bench/gpu-bundle.sh recorded in .gpu/commit.json; else HEAD of this
    checkout (and whether the tree differs from it)."""
    recorded = os.path.join(ROOT, ".gpu", "commit.json")
    if os.environ.get("GPU_FILES") and os.path.exists(recorded):
        with open(recorded) as f:
            c = json.load(f)
        c["source"] = "bundle"
        return c
    try:
        head = subprocess.run(["git", "-C", ROOT, "rev-parse", "HEAD"], capture_output=True,
                              text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, check=True).stdout.strip() != ""
        return {"commit": head, "dirty": dirty, "source": "git"}
    except (OSError, subprocess.CalledProcessError):
        pass
    return {"commit": "unknown", "dirty": None, "source": "none"}


def nvidia_smi():
    try:
        out = subprocess.run(["nvidia-smi", "--query-gpu=name,driver_version,clocks.max.sm",
                              "--format=csv,noheader"], capture_output=True, text=True,
                             timeout=20, check=True).stdout.strip().splitlines()
    except (OSError, subprocess.SubprocessError):
        return None
    if not out:
        return None
    name, driver, clock = [x.strip() for x in out[0].split(",")]
    return {"gpu": name, "driver": driver, "max_sm_clock": clock, "gpu_count": len(out)}


def expand_cases(group):
    """A case is a string (an OIT technique) or an object; group keys are the defaults."""
    cases = []
    for c in group["cases"]:
        c = {"name": c, "oit": c} if isinstance(c, str) else dict(c)
        for key in ("scene", "oit", "width", "height", "warmup", "frames", "timeout_s"):
            if key not in c and key in group:
                c[key] = group[key]
        c["set"] = list(group.get("set", [])) + list(c.get("set", []))
        c["quick_set"] = list(group.get("quick_set", [])) + list(c.get("quick_set", []))
        c["options"] = list(group.get("options", [])) + list(c.get("options", []))
        c["args"] = list(group.get("args", [])) + list(c.get("args", []))
        cases.append(c)
    names = [c["name"] for c in cases]
    if len(set(names)) != len(names):
        raise SystemExit(f"run.py: group {group['name']}: case names repeat: {names}")
    return cases


def run_process(cmd, timeout_s):
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=timeout_s)
        return p.returncode, p.stderr[-2000:], time.monotonic() - t0
    except subprocess.TimeoutExpired:
        return 124, f"timed out after {timeout_s} s", time.monotonic() - t0


def metric_of(raw, metric):
    """'frame': the median over frames of the frame's summed pass times; a list of pass names
    (fnmatch patterns such as 'shadow*'): the sum of those passes' medians."""
    if metric == "frame":
        return raw.get("total_median_ms", raw.get("gpu_total_median_ms"))
    names = [metric] if isinstance(metric, str) else metric
    total, hit = 0.0, False
    for p in raw.get("passes", []):
        if any(fnmatch.fnmatchcase(p["name"], n) for n in names):
            total += p["median_ms"]
            hit = True
    return total if hit else None


def bench_case(tool, case, metric, tmp):
    out = os.path.join(tmp, "case.json")
    if os.path.exists(out):
        os.remove(out)
    cmd = [tool, case["scene"], "--width", str(case.get("width", 1920)),
           "--height", str(case.get("height", 1080)), "--frames", str(case.get("frames", 30)),
           "--warmup", str(case.get("warmup", 8))]
    if case.get("oit"):
        cmd += ["--oit", case["oit"]]
    for s in case["set"] + (case["quick_set"] if QUICK else []):
        cmd += ["--set", s]
    cmd += case["options"] + ["--json", out]
    if QUICK:
        cmd[2:10] = ["--width", "64", "--height", "36", "--frames", "1", "--warmup", "0"]
    rc, err, wall = run_process(cmd, case.get("timeout_s", 150) * (4 if QUICK else 1))
    record = {"name": case["name"], "command": [os.path.basename(tool)] + cmd[1:-2],
              "wall_s": round(wall, 2)}
    if rc != 0 or not os.path.exists(out):
        record["error"] = f"exit {rc}: {err.strip()}"
        return record, None
    with open(out) as f:
        raw = json.load(f)
    record.update(case_record(raw, metric))
    return record, raw


def case_record(raw, metric):
    """A case's entry from veil-bench's JSON: passes (median, min, max), the frame totals,
    the group's metric, and the rest of what veil-bench wrote as `detail`."""
    raw = dict(raw)
    record = {"passes": raw.get("passes", []), "metric_ms": metric_of(raw, metric)}
    raw.pop("passes", None)
    for key in ("total_median_ms", "total_min_ms", "total_max_ms", "gpu_total_median_ms"):
        if key in raw:
            record[key] = raw.pop(key)
    record["detail"] = raw  # scene, oit, shadows, stats, renderer, ... as veil-bench wrote them
    return record


def voxbench_group(tool, group, tmp):
    """One veil-voxbench process per case; each result row (method x resolution x slices)
    becomes a case named 'CASE/METHOD rRES sSLICES'."""
    records, info = [], None
    for case in expand_cases(group):
        out = os.path.join(tmp, "vox.json")
        if os.path.exists(out):
            os.remove(out)
        cmd = [tool, case["scene"]] + case["args"] + case["options"] + ["--json", out]
        rc, err, wall = run_process(cmd, case.get("timeout_s", 300))
        if rc != 0 or not os.path.exists(out):
            records.append({"name": case["name"], "command": ["veil-voxbench"] + cmd[1:-2],
                            "error": f"exit {rc}: {err.strip()}"})
            continue
        with open(out) as f:
            raw = json.load(f)
        info = info or raw
        for row in raw.get("results", []):
            method = row["method"].split(" ")[0]
            label = f"{method} r{row['res']}" + (f" s{row['slices']}" if "slices" in row else "")
            name = label if case["name"] == "-" else f"{case['name']}/{label}"
            records.append({"name": name, "command": ["veil-voxbench"] + cmd[1:-2],
                            "wall_s": round(wall, 2), "metric_ms": row["median_ms"],
                            "min_ms": row.get("min_ms"), "max_ms": row.get("max_ms"),
                            "detail": row})
    return records, info


def python_interpreter():
    """The interpreter for tool "python" groups: $VEIL_PYTHON, else Debian's /usr/bin/python3
    (the one the module is built for, with NumPy), else this one."""
    return os.environ.get("VEIL_PYTHON") or (
        "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable)


def python_group(group, tmp):
    """Tool "python": the group's script (bench/python_overhead.py) once per case, with the
    module from $VEIL_PYTHONPATH (default build/release/python); two records per case, the
    Python loop and the C++ loop, metric = total wall ms of the frames."""
    records, info = [], None
    for case in expand_cases(group):
        out = os.path.join(tmp, "py.json")
        if os.path.exists(out):
            os.remove(out)
        frames = 2 if QUICK else case.get("frames", 100)
        cmd = [python_interpreter(), group["script"], case["scene"],
               "--width", str(case.get("width", 64)), "--height", str(case.get("height", 64)),
               "--frames", str(frames), "--warmup", str(0 if QUICK else case.get("warmup", 3))]
        cmd += case["args"] + ["--json", out]
        env_path = os.environ.get("VEIL_PYTHONPATH", os.path.join(ROOT, "build", "release",
                                                                 "python"))
        old = os.environ.get("PYTHONPATH")
        os.environ["PYTHONPATH"] = env_path
        try:
            rc, err, wall = run_process(cmd, case.get("timeout_s", 600))
        finally:
            if old is None:
                os.environ.pop("PYTHONPATH")
            else:
                os.environ["PYTHONPATH"] = old
        prefix = "" if case["name"] == "-" else case["name"] + "/"
        if rc != 0 or not os.path.exists(out):
            records.append({"name": prefix + "Python loop", "command": cmd[1:-2],
                            "error": f"exit {rc}: {err.strip()}"})
            continue
        with open(out) as f:
            raw = json.load(f)
        info = info or raw
        for label, key in (("Python loop", "python"), ("C++ loop", "cpp")):
            records.append({"name": prefix + label, "command": cmd[1:-2],
                            "wall_s": round(wall, 2), "metric_ms": 1e3 * raw[key]["total_s"],
                            "median_ms": raw[key]["median_ms"], "detail": raw[key]})
    return records, info


def clock_warmup(tool, seconds):
    """Throwaway frames until `seconds` have passed: clocks ramp up at the start of a call."""
    if seconds <= 0:
        return
    log(f"clock warm-up: {seconds} s of throwaway frames")
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        rc, err, _ = run_process([tool, "datasets/scenes/room.json", "--width", "1920", "--height",
                                  "1080", "--frames", "300", "--warmup", "0"], 120)
        if rc != 0:
            log(f"clock warm-up frames failed: {err.strip()}")
            return


def generated_scene(tool, group, tmp):
    """A group with "generate" renders a sequence that veil-seqgen writes first (real .vdb
    files of about `voxels` active voxels per frame, into the run's temporary folder): the
    group's scene (a template beside which the frames are expected as cloud_#.vdb) is copied
    there with the volume scaled so the cloud's ball has a radius of 1 whatever its voxel count.
    Returns (scene path, generation record); the scene is None when generation failed."""
    g = group["generate"]
    folder = os.path.join(tmp, re.sub(r"[^a-z0-9]+", "-", group["name"].lower()).strip("-"))
    os.makedirs(folder, exist_ok=True)
    cmd = [tool, "--voxels", str(g["voxels"]), "--frames", g["frames"],
           "-o", os.path.join(folder, "cloud_#.vdb")]
    rc, err, wall = run_process(cmd, g.get("timeout_s", 600))
    record = {"command": [os.path.basename(tool)] + cmd[1:-2], "wall_s": round(wall, 2)}
    if rc != 0:
        record["error"] = f"exit {rc}: {err.strip()}"
        return None, record
    with open(os.path.join(ROOT, group["scene"])) as f:
        scene = json.load(f)
    # veil-seqgen's ball: N = 4/3 pi r^3 x 1.04 voxels of size 1 about the origin.
    n = float(str(g["voxels"]).rstrip("KkMm")) * {"k": 1e3, "m": 1e6}.get(
        str(g["voxels"])[-1].lower(), 1.0)
    radius = (n / (4.0 / 3.0 * math.pi * 1.04)) ** (1.0 / 3.0)
    for v in scene["volumes"]:
        v["transform"] = {"scale": 1.0 / radius}
    path = os.path.join(folder, os.path.basename(group["scene"]))
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    record["radius_voxels"] = round(radius, 1)
    return path, record


def dataset_scene(group, tmp):
    """A group with "frames_dir" renders files that are not in the repository (too large):
    the environment variable it names holds their folder (e.g. the 60-frame EmberGen fire of
    the team's shared datasets, bundled as an extra folder, bench/README.md). The group's
    scene is copied to the run's temporary folder with each volume's file pattern moved into
    that folder. Returns (scene path, error); the scene is None when the folder is missing."""
    var = group["frames_dir"]
    folder = os.environ.get(var, "")
    if not folder or not os.path.isdir(folder):
        return None, f"set {var} to the folder of the frames (bench/README.md)"
    with open(os.path.join(ROOT, group["scene"])) as f:
        scene = json.loads(re.sub(r"^\s*//.*$", "", f.read(), flags=re.M))
    for v in scene["volumes"]:
        v["path"] = os.path.join(os.path.abspath(folder), os.path.basename(v["path"]))
    path = os.path.join(tmp, os.path.basename(group["scene"]))
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path, None


def run_set(path, s, tools, args, save=None):
    started = datetime.datetime.now(datetime.timezone.utc)
    warm = s.get("clock_warmup_s", 20) if args.clock_warmup is None else args.clock_warmup
    clock_warmup(tools["veil-bench"], warm)
    result = {"schema": SCHEMA, "set": s["name"], "description": s.get("description", ""),
              "set_file": os.path.relpath(path, ROOT), "started": started.isoformat(timespec="seconds"),
              "settings": {"clock_warmup_s": warm, "set": s, "quick": QUICK}, "machine": {}, "groups": []}
    machine = {"host_cpu": platform.processor() or platform.machine(),
               "cpu_count": os.cpu_count()}
    smi = nvidia_smi()
    if smi:
        machine.update(smi)
    result.update(git_commit_fields())
    with tempfile.TemporaryDirectory() as tmp:
        for group in s["groups"]:
            tool_name = group.get("tool", "veil-bench")
            metric = group.get("metric", "frame")
            log(f"[{s['name']}] {group['name']}")
            if tool_name == "python":
                records, info = python_group(group, tmp)
                if info:
                    machine.setdefault("renderer", info["renderer"])
                    machine.setdefault("gl_version", info["gl_version"])
            elif tool_name == "veil-voxbench":
                records, info = voxbench_group(tools[tool_name], group, tmp)
                if info and "renderer" in info:
                    machine.setdefault("renderer", info["renderer"])
                    machine.setdefault("timer", "GL_TIME_ELAPSED")
            else:
                records, cases = [], expand_cases(group)
                generated = None
                if "generate" in group:
                    scene_path, generated = generated_scene(tools["veil-seqgen"], group, tmp)
                    log(f"  generated {group['generate']['voxels']} voxels x "
                        f"{group['generate']['frames']}: {generated['wall_s']} s"
                        + (f" FAILED {generated['error'][:300]}" if "error" in generated else ""))
                    for case in cases:
                        case["scene"] = scene_path
                if "frames_dir" in group:
                    scene_path, missing = dataset_scene(group, tmp)
                    if missing:
                        log(f"  skipped: {missing}")
                    for case in cases:
                        case["scene"] = scene_path
                for case in cases:
                    if "frames_dir" in group and case["scene"] is None:
                        records.append({"name": case["name"], "error": missing})
                        continue
                    if "generate" in group and case["scene"] is None:
                        records.append({"name": case["name"], "error": "generation failed"})
                        continue
                    rec, raw = bench_case(tools[tool_name], case, metric, tmp)
                    if raw:
                        machine.setdefault("renderer", raw.get("renderer"))
                        if raw.get("gl_version"):
                            machine.setdefault("gl_version", raw["gl_version"])
                        if raw.get("timer"):
                            machine.setdefault("timer", raw["timer"])
                    if "error" in rec:
                        log(f"  {case['name']}: FAILED {rec['error'][:300]}")
                    else:
                        log(f"  {case['name']}: {rec['metric_ms']:.3f} ms")
                    records.append(rec)
            base_name = group.get("baseline")
            base = next((r for r in records if r["name"] == base_name), None)
            base_ms = base.get("metric_ms") if base else None
            for r in records:
                if base_ms and r.get("metric_ms") is not None:
                    r["ratio"] = r["metric_ms"] / base_ms
            entry = {
                "name": group["name"], "tool": tool_name,
                "metric": metric, "baseline": base_name,
                "description": group.get("description", ""), "cases": records}
            if tool_name not in ("python", "veil-voxbench") and generated:
                entry["generated"] = generated
            result["groups"].append(entry)
            if save:
                save(result)  # the groups so far survive a run stopped at its time limit
    if "driver" not in machine and machine.get("gl_version"):
        m = re.search(r"NVIDIA ([0-9.]+)|Mesa ([0-9.]+\S*)", machine["gl_version"])
        if m:
            machine["driver"] = m.group(0)
    machine.setdefault("gpu", (machine.get("renderer") or "unknown").split("/")[0])
    result["machine"] = machine
    result["finished"] = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    return result


def git_commit_fields():
    c = git_commit()
    return {"commit": c.get("commit", "unknown"), "commit_dirty": c.get("dirty"),
            "commit_source": c.get("source")}


def slug(text):
    text = re.sub(r"^NVIDIA\s+", "", text)
    text = re.sub(r"\s*\(.*\)", "", text.split("/")[0])
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")[:24] or "unknown"


def dry_run(sets):
    """Every case's command, and a check that the scenes exist and baselines name a case."""
    bad = 0
    for path, s in sets:
        for group in s["groups"]:
            cases = expand_cases(group)
            names = [c["name"] for c in cases]
            tool = group.get("tool", "veil-bench")
            if tool not in ("veil-bench", "veil-voxbench", "veil-seqbench", "python"):
                log(f"{path}: group {group['name']}: unknown tool {tool}")
                bad += 1
            base = group.get("baseline")
            if base and tool in ("veil-bench", "veil-seqbench") and base not in names:
                log(f"{path}: group {group['name']}: baseline {base!r} is not a case")
                bad += 1
            if "generate" in group and (tool != "veil-seqbench" or not {"voxels", "frames"}
                                        <= set(group["generate"])):
                log(f"{path}: group {group['name']}: generate needs veil-seqbench, voxels, frames")
                bad += 1
            for c in cases:
                if not os.path.exists(os.path.join(ROOT, c.get("scene", ""))):
                    log(f"{path}: {group['name']}/{c['name']}: no scene {c.get('scene')}")
                    bad += 1
                extra = [a for x in c["set"] for a in ("--set", x)] + c["options"] + c["args"]
                print(f"{s['name']} | {group['name']} | {c['name']}: {tool} {c.get('scene')} "
                      + (f"--oit {c['oit']} " if c.get("oit") else "") + " ".join(extra))
    return 1 if bad else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sets", nargs="+", help="set names (bench/sets/NAME.json) or set files")
    ap.add_argument("--out", help="folder for the JSON files (default: $OUT on the GPU "
                    "machine, else bench/results)")
    ap.add_argument("--bin", help="folder with veil-bench and veil-voxbench")
    ap.add_argument("--clock-warmup", type=float, help="seconds of throwaway frames before "
                    "the first case (default: the set's clock_warmup_s)")
    ap.add_argument("--name", help="output file name (one set only; default "
                    "DATE-GPU-SET.json)")
    ap.add_argument("--check", action="store_true", help="validate each run file written "
                    "(bench/report.py --check) and fail on any problem")
    ap.add_argument("--quick", action="store_true", help="smoke test of a set on any "
                    "driver: 64x36, no warm-up, one frame (numbers are meaningless)")
    ap.add_argument("--dry-run", action="store_true", help="check the sets and print the "
                    "commands without running them")
    args = ap.parse_args()
    sets = [load_set(a) for a in args.sets]
    if args.quick:
        global QUICK
        QUICK = True
        args.clock_warmup = 0
    if args.dry_run:
        return dry_run(sets)
    out_dir = args.out or os.environ.get("OUT") or os.path.join(ROOT, "bench", "results")
    os.makedirs(out_dir, exist_ok=True)
    needed = {g.get("tool", "veil-bench") for _, s in sets for g in s["groups"]} | {"veil-bench"}
    needed.discard("python")  # a script run by python_interpreter(), not a program
    if any("generate" in g for _, s in sets for g in s["groups"]):
        needed.add("veil-seqgen")
    tools = {t: find_tool(t, args.bin) for t in sorted(needed)}
    os.environ.setdefault("VEIL_SHADER_DIR", os.path.join(ROOT, "shaders"))
    failed = 0
    for path, s in sets:
        partial = os.path.join(out_dir, (args.name if args.name and len(sets) == 1 else
                                         s["name"] + ".json") + ".partial")

        def save(result, partial=partial):
            with open(partial + ".tmp", "w") as f:
                json.dump(dict(result, partial=True), f, indent=1)
            os.replace(partial + ".tmp", partial)
        result = run_set(path, s, tools, args, save)
        name = args.name if args.name and len(sets) == 1 else \
            f"{result['started'][:10]}-{slug(result['machine']['gpu'])}-{s['name']}.json"
        target = os.path.join(out_dir, name)
        with open(target + ".tmp", "w") as f:
            json.dump(result, f, indent=1)
            f.write("\n")
        os.replace(target + ".tmp", target)
        if os.path.exists(partial):
            os.remove(partial)
        failed += sum(1 for g in result["groups"] for c in g["cases"] if "error" in c)
        print(report.set_section(result, heading="##"))
        log(f"wrote {target}")
        if args.check:
            problems = report.check_run(result)
            for p in problems:
                log(f"{target}: {p}")
            failed += len(problems)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
