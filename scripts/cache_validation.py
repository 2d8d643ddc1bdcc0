#!/usr/bin/env python3
"""The scattered-light cache's GPU frame against the path tracer, over conditions fixed here.

    scripts/cache_validation.py render [--budget S] [--work DIR] [--out DIR] [--bin DIR] [--quick]
    scripts/cache_validation.py table FOLDER_OR_TGZ [--out table.md]

`render` (from the repository root, on the GPU machine after `source .gpu/env.sh`): for every
condition below, the GPU frame with the cache, the GPU frame with single scattering (the cache
off, `fog_ambient` 1) and the path tracer's reference (veil-bench --pathtraced, all bounces;
for the floor veil-bench --surface-pathtraced), all at 128x128. The GPU frames run in a thread
beside the path tracer (which takes every core). The reference is made of chunks with seeds
1001, 1002, ...: a pilot chunk per condition measures its time and noise, then chunks go to the
conditions whose noise over 4x4-pixel blocks is still above --noise (0.02), by estimated time,
until the wall-clock --budget (seconds from the start) would be passed. The chunks' mean and
its standard error are merged per condition. Resumable: finished files in --work (default
build/cache-validation) are kept and skipped. After every finished file the frames, the merged
references and manifest.json are packed into OUT/validation.tgz (OUT: --out, else $OUT, else
the work folder). --quick: 32x32, 4-sample chunks, the caches at 8 voxels per texel and 4
paths, a 60 s budget (a smoke test of the whole chain on any machine).

`table` (here, Python 3 alone): reads the folder or validation.tgz and writes the markdown
table: per condition the mean relative error of Y (Rec. 709 luminance) over 4x4-pixel blocks
(the blocks whose reference differs from the background by more than 2 % of it, as
scripts/volume_error.py --bin 4), its 99th percentile, the bias of the mean luminance over
those blocks, the reference's own mean relative standard error per block, and single
scattering's error for comparison; the worst condition named. Standard library only.
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tarfile
import threading
import time
from array import array

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CLOUD = "datasets/scenes/cloud-wdas.json"
SKY = (0.12, 0.16, 0.24)
FIRE_BG = (0.01, 0.01, 0.015)
FIRE_CACHE = ["render.fog_scattered_light=true", "render.fog_scattered_light_samples=64",
              "render.fog_scattered_light_cell=4"]
# name, label, scene, --set overrides, background (the mask's), kind. Fixed before any result
# was seen; light directions are the light's travel direction.
CONDITIONS = [
    ("shipped", "Disney cloud, shipped view (sun behind the camera, g 0.6)", CLOUD, [], SKY,
     "volume"),
    ("backlit", "sun behind the cloud toward the camera, g 0.85", CLOUD,
     ["lights.0.direction=[0.2,-0.25,0.95]", "volumes.0.anisotropy=0.85"], SKY, "volume"),
    ("side", "side sun (from the right, 14 deg up)", CLOUD,
     ["lights.0.direction=[-0.97,-0.25,0.0]"], SKY, "volume"),
    ("low", "low sun (8 deg up, behind the camera's left)", CLOUD,
     ["lights.0.direction=[0.6,-0.14,-0.79]"], SKY, "volume"),
    ("thin", "density x0.25", CLOUD, ["volumes.0.density_scale=10"], SKY, "volume"),
    ("dense", "density x3", CLOUD, ["volumes.0.density_scale=120"], SKY, "volume"),
    ("iso", "isotropic phase (g 0)", CLOUD, ["volumes.0.anisotropy=0"], SKY, "volume"),
    ("albedo", "albedo 0.9", CLOUD, ["volumes.0.albedo=0.9"], SKY, "volume"),
    ("smoke", "smoke VDB (fog.json's smoke at 8x density, albedo 0.95, g 0.35, sun + sky)",
     "bench/scenes/cache-validation-smoke.json", [], SKY, "volume"),
    ("fire", "EmberGen fire with emission (fire.json, cache 4 voxels/texel)",
     "datasets/scenes/fire.json", FIRE_CACHE, FIRE_BG, "volume"),
    ("floor", "floor under the fire (fire-floor.json, no moon): surface light",
     "bench/scenes/cache-validation-floor.json", [], (0.0, 0.0, 0.0), "surface"),
    ("floor-low", "the same floor 8 voxels lower (2 texels below the grid): surface light",
     "bench/scenes/cache-validation-floor-low.json", [], (0.0, 0.0, 0.0), "surface"),
]
# Rows of the table that are a region of another condition's images: the backlit cloud's lit
# rim, its blocks brighter than 1.2x the sky in the reference.
REGIONS = [("backlit-rim", "backlit, g 0.85: the lit rim alone (blocks > 1.2x the sky)",
            "backlit", 1.2)]
SINGLE = ["render.fog_scattered_light=false", "render.fog_ambient=1", "render.fog_octaves=1"]
# The cache frames bake the whole cache before the frame (as `veil render`; the viewer's
# progressive bake would draw a partial one).
FULL_BAKE = ["render.fog_scattered_light_budget_ms=0"]
QUICK_CACHE = ["render.fog_scattered_light_samples=4", "render.fog_scattered_light_cell=8"]
# The error each condition must stay within (mean relative error over 4x4 blocks); the floor's
# is the surface target (docs/scattered-light.md "Surfaces lit by the cache"). The reference's noise
# per block is brought under a fifth of it (--noise scales the volumes' 0.02).
TARGET = {"floor": 0.15, "floor-low": 0.15}
SEED0 = 1001
BLOCK = 4
LUMA = (0.2126, 0.7152, 0.0722)


def log(msg):
    print(msg, flush=True)


# --- PFM images: (width, height, RGB floats top row first) -------------------------------------

def read_pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    m = re.match(rb"(PF|Pf)\s+(\d+)\s+(\d+)\s+(\S+)\s", data)
    if not m:
        raise SystemExit(f"cache_validation: {path}: not a PFM file")
    ch = 3 if m.group(1) == b"PF" else 1
    w, h, scale = int(m.group(2)), int(m.group(3)), float(m.group(4))
    px = array("f")
    px.frombytes(data[m.end():m.end() + 4 * w * h * ch])
    if len(px) != w * h * ch:
        raise SystemExit(f"cache_validation: {path}: truncated ({len(px)} of {w * h * ch} values)")
    if (scale < 0) != (sys.byteorder == "little"):
        px.byteswap()
    rows = [px[(h - 1 - y) * w * ch:(h - y) * w * ch] for y in range(h)]  # bottom-up on disk
    out = array("f")
    for r in rows:
        out.extend(r if ch == 3 else array("f", [v for v in r for _ in range(3)]))
    return w, h, out


def write_pfm(path, w, h, rgb):
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(f"PF\n{w} {h}\n-1.0\n".encode())
        for y in range(h - 1, -1, -1):
            row = array("f", rgb[y * w * 3:(y + 1) * w * 3])
            if sys.byteorder != "little":
                row.byteswap()
            f.write(row.tobytes())
    os.replace(tmp, path)


def luminance(rgb):
    return [LUMA[0] * rgb[i] + LUMA[1] * rgb[i + 1] + LUMA[2] * rgb[i + 2]
            for i in range(0, len(rgb), 3)]


def bin_blocks(y, w, h, k, squares=False):
    """Means of k x k blocks (of the squares: for standard errors, sqrt(sum se^2) / k^2)."""
    bw, bh = w // k, h // k
    out = [0.0] * (bw * bh)
    for py in range(bh * k):
        row = py * w
        base = (py // k) * bw
        for px in range(bw * k):
            v = y[row + px]
            out[base + px // k] += v * v if squares else v
    n = k * k
    return [math.sqrt(v) / n for v in out] if squares else [v / n for v in out]


def percentile(values, q):
    """numpy.percentile's default (linear between the closest ranks)."""
    s = sorted(values)
    if not s:
        return float("nan")
    pos = (len(s) - 1) * q / 100.0
    lo = int(math.floor(pos))
    hi = min(lo + 1, len(s) - 1)
    return s[lo] + (s[hi] - s[lo]) * (pos - lo)


def compare(ref_y, ref_se, img_y, w, h, background, region=None):
    """The 4x4-block statistics of one image against the reference (luminance lists)."""
    ref = bin_blocks(ref_y, w, h, BLOCK)
    se = bin_blocks(ref_se, w, h, BLOCK, squares=True)
    img = bin_blocks(img_y, w, h, BLOCK)
    bg = sum(c * l for c, l in zip(background, LUMA))
    mask = [abs(r - bg) > 0.02 * bg for r in ref]
    if region is not None:
        mask = [m and r > region * bg for m, r in zip(mask, ref)]
    idx = [i for i, m in enumerate(mask) if m]
    if not idx:
        return None
    rel = [abs(img[i] - ref[i]) / max(ref[i], 1e-6) for i in idx]
    return {"blocks": len(idx), "of": len(ref),
            "mean": sum(rel) / len(rel), "p99": percentile(rel, 99),
            "bias": sum(img[i] - ref[i] for i in idx) / sum(ref[i] for i in idx),
            "noise": sum(se[i] / max(ref[i], 1e-6) for i in idx) / len(idx),
            "ref_mean_y": sum(ref[i] for i in idx) / len(idx)}


# --- render --------------------------------------------------------------------------------

def find_bench(bin_dir):
    for cand in ([os.path.join(bin_dir, "veil-bench")] if bin_dir else []) + \
            [shutil.which("veil-bench") or "", os.path.join(ROOT, "build/release/bench/veil-bench")]:
        if cand and os.access(cand, os.X_OK):
            return cand
    raise SystemExit("cache_validation: veil-bench not found (--bin DIR, PATH or "
                     "build/release/bench/; on the GPU machine: source .gpu/env.sh)")


def run_tool(cmd, log_path):
    t0 = time.time()
    with open(log_path, "w") as lf:
        r = subprocess.run(cmd, cwd=ROOT, stdout=lf, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        with open(log_path) as lf:
            tail = lf.read()[-2000:]
        raise RuntimeError(f"{' '.join(cmd)} failed ({r.returncode}):\n{tail}")
    return time.time() - t0


class Packer:
    """Packs the frames, merged references and manifest into OUT/validation.tgz after each
    finished file (atomically: a killed run leaves the last complete archive)."""

    def __init__(self, work, out):
        self.work, self.out, self.lock = work, out, threading.Lock()

    def pack(self):
        with self.lock:
            # Not the chunks (ref-NAME-sSEED-SPP*): their merge is ref-NAME.pfm.
            names = sorted(n for n in os.listdir(self.work) if n == "manifest.json" or (
                re.fullmatch(r"(gpu-.*\.(pfm|json)|ref-.*\.pfm)", n)
                and not re.search(r"-s\d+-\d+", n)))
            tmp = os.path.join(self.out, ".validation.tgz.tmp")
            with tarfile.open(tmp, "w:gz", compresslevel=1) as tar:
                for n in names:
                    tar.add(os.path.join(self.work, n), arcname=f"validation/{n}")
            os.replace(tmp, os.path.join(self.out, "validation.tgz"))


def chunk_files(work, name):
    """The finished reference chunks of a condition: [(seed, spp, seconds, pfm path)]."""
    out = []
    for n in sorted(os.listdir(work)):
        m = re.fullmatch(rf"ref-{re.escape(name)}-s(\d+)-(\d+)\.json", n)
        if m and os.path.exists(os.path.join(work, n[:-5] + "-stderr.pfm")):
            with open(os.path.join(work, n)) as f:
                sec = json.load(f)["seconds"]
            out.append((int(m.group(1)), int(m.group(2)), sec, os.path.join(work, n[:-5] + ".pfm")))
    return out


def merge(work, name):
    """The spp-weighted mean of the chunks and its standard error: ref-NAME(.pfm, -stderr.pfm);
    returns (total spp, seconds, noise per block)."""
    chunks = chunk_files(work, name)
    total = sum(c[1] for c in chunks)
    mean = var = None
    for _, spp, _, path in chunks:
        w, h, m = read_pfm(path)
        _, _, se = read_pfm(path[:-4] + "-stderr.pfm")
        wt = spp / total
        if mean is None:
            mean, var = [0.0] * len(m), [0.0] * len(m)
        for i in range(len(m)):
            mean[i] += wt * m[i]
            var[i] += (wt * se[i]) ** 2
    se = [math.sqrt(v) for v in var]
    write_pfm(os.path.join(work, f"ref-{name}.pfm"), w, h, mean)
    write_pfm(os.path.join(work, f"ref-{name}-stderr.pfm"), w, h, se)
    cond = next(c for c in CONDITIONS if c[0] == name)
    bg = cond[4]
    bgy = sum(c * l for c, l in zip(bg, LUMA))
    ref = bin_blocks(luminance(mean), w, h, BLOCK)
    seb = bin_blocks(luminance(se), w, h, BLOCK, squares=True)
    sel = [s / max(r, 1e-6) for r, s in zip(ref, seb) if abs(r - bgy) > 0.02 * bgy]
    noise = sum(sel) / len(sel) if sel else float("nan")
    return total, sum(c[2] for c in chunks), noise


def render(args):
    bench = find_bench(args.bin)
    work = os.path.abspath(args.work or os.path.join(ROOT, "build", "cache-validation"))
    out = os.path.abspath(args.out or os.environ.get("OUT") or work)
    os.makedirs(work, exist_ok=True)
    os.makedirs(out, exist_ok=True)
    size = 32 if args.quick else 128
    budget = args.budget if args.budget is not None else (60.0 if args.quick else 400.0)
    pilot = 4 if args.quick else 16
    names = [c[0] for c in CONDITIONS]
    unknown = [n for n in (args.only.split(",") if args.only else []) if n not in names]
    if unknown:
        raise SystemExit(f"cache_validation: --only: unknown condition {', '.join(unknown)} "
                         f"(one of {', '.join(names)})")
    conds = [c for c in CONDITIONS if not args.only or c[0] in args.only.split(",")]
    t_start = time.time()
    packer = Packer(work, out)
    manifest_lock = threading.Lock()
    manifest = {"size": size, "quick": args.quick, "block": BLOCK, "noise_target": args.noise,
                "budget_s": budget, "bench": bench, "conditions": {}}
    mpath = os.path.join(work, "manifest.json")
    if os.path.exists(mpath):
        with open(mpath) as f:
            old = json.load(f)
        if old.get("size") != size:
            raise SystemExit(f"cache_validation: {work} holds a {old.get('size')}x"
                             f"{old.get('size')} run, not {size}x{size}: give another --work "
                             "(or remove it)")
        manifest["conditions"] = old.get("conditions", {})
    for name, label, scene, sets, bg, kind in conds:
        manifest["conditions"].setdefault(name, {}).update(
            {"label": label, "scene": scene, "set": sets, "background": list(bg), "kind": kind})
    commit = os.path.join(ROOT, ".gpu", "commit.json")  # bench/gpu-bundle.sh's, on the GPU machine
    if os.path.exists(commit):
        with open(commit) as f:
            manifest["bundle"] = json.load(f)
    manifest["cpus"] = os.cpu_count()
    manifest["regions"] = [{"name": r[0], "label": r[1], "of": r[2], "above_background": r[3]}
                           for r in REGIONS]

    def save_manifest():
        with manifest_lock:
            tmp = mpath + ".tmp"
            with open(tmp, "w") as f:
                json.dump(manifest, f, indent=1)
            os.replace(tmp, mpath)
        packer.pack()

    def elapsed():
        return time.time() - t_start

    extra = QUICK_CACHE if args.quick else []
    common = ["--width", str(size), "--height", str(size)]
    errors = []

    def gpu_frames():
        for name, _, scene, sets, _, _ in conds:
            for variant, vsets in (("cache", FULL_BAKE + extra), ("single", SINGLE)):
                stem = os.path.join(work, f"gpu-{name}-{variant}")
                if os.path.exists(stem + ".pfm") and os.path.exists(stem + ".json"):
                    continue
                cmd = [bench, scene, *common, "--frames", "1", "--warmup", "0", "--pfm",
                       stem + ".pfm", "--json", stem + ".json"]
                for s in sets + vsets:
                    cmd += ["--set", s]
                try:
                    sec = run_tool(cmd, stem + ".log")
                except RuntimeError as e:
                    errors.append(str(e))
                    log(f"[{elapsed():6.1f} s] GPU {name} {variant}: FAILED (see {stem}.log)")
                    continue
                with open(stem + ".json") as f:
                    bake = [p["median_ms"] for p in json.load(f)["passes"]
                            if p["name"] == "scattered_light_bake"]
                with manifest_lock:
                    manifest["conditions"][name][f"gpu_{variant}_s"] = round(sec, 2)
                    if bake:
                        manifest["conditions"][name]["bake_ms"] = bake[0]
                log(f"[{elapsed():6.1f} s] GPU {name} {variant}: {sec:.1f} s"
                    + (f" (bake {bake[0]:.0f} ms)" if bake else ""))
                save_manifest()

    gpu = threading.Thread(target=gpu_frames)
    gpu.start()

    def chunk(name, scene, sets, kind, seed, spp):
        stem = os.path.join(work, f"ref-{name}-s{seed}-{spp}")
        mode = "--surface-pathtraced" if kind == "surface" else "--pathtraced"
        cmd = [bench, scene, mode, str(spp), str(seed), stem + ".pfm", *common, "--json",
               stem + ".json"]
        for s in sets:
            cmd += ["--set", s]
        sec = run_tool(cmd, stem + ".log")
        total, seconds, noise = merge(work, name)
        with manifest_lock:
            manifest["conditions"][name].update(
                {"ref_spp": total, "ref_seconds": round(seconds, 2), "ref_noise": noise,
                 "ref_seeds": sorted(c[0] for c in chunk_files(work, name))})
        log(f"[{elapsed():6.1f} s] reference {name}: +{spp} spp (seed {seed}) in {sec:.1f} s; "
            f"{total} spp, noise per block {noise:.4f}")
        save_manifest()

    # The pilots: one chunk per condition (kept from an earlier run where present).
    for name, _, scene, sets, _, kind in conds:
        if not chunk_files(work, name):
            try:
                chunk(name, scene, sets, kind, SEED0, pilot)
            except RuntimeError as e:
                errors.append(str(e))
                log(f"reference {name}: FAILED")
        elif "ref_noise" not in manifest["conditions"][name]:
            total, seconds, noise = merge(work, name)
            manifest["conditions"][name].update({"ref_spp": total, "ref_seconds": seconds,
                                                 "ref_noise": noise})
    # Then chunks where the noise is above the target, the noisiest (relative to the target)
    # first, each sized to reach the target (at most 4x the samples so far) when it fits the
    # time left.
    while True:
        best = None
        for name, _, scene, sets, _, kind in conds:
            c = manifest["conditions"][name]
            goal = args.noise * TARGET.get(name, 0.10) / 0.10
            if "ref_noise" not in c or not c["ref_noise"] > goal:
                continue
            need = c["ref_spp"] * ((c["ref_noise"] / goal) ** 2 - 1.0)
            spp = int(min(max(need, pilot), 4 * c["ref_spp"]))
            spp = max(pilot, int(math.ceil(spp / pilot)) * pilot)
            rate = c["ref_seconds"] / c["ref_spp"]  # seconds per spp
            left = budget - elapsed()
            if rate * spp > left:
                spp = int(left / rate / pilot) * pilot
            if spp < pilot:
                continue
            key = c["ref_noise"] / goal
            if best is None or key > best[0]:
                seeds = [s for s, *_ in chunk_files(work, name)]
                best = (key, name, scene, sets, kind, max(seeds) + 1, spp)
        if best is None:
            break
        try:
            chunk(*best[1:])
        except RuntimeError as e:
            errors.append(str(e))
            log(f"reference {best[1]}: FAILED")
            break
    gpu.join()
    manifest["elapsed_s"] = round(elapsed(), 1)
    save_manifest()
    for e in errors:
        log(f"error: {e}")
    log(f"[{elapsed():6.1f} s] done: {os.path.join(out, 'validation.tgz')}")
    return 1 if errors else 0


# --- table ---------------------------------------------------------------------------------

def load_folder(src):
    """A folder of files, from a folder or validation.tgz: {name: bytes-path}."""
    if os.path.isdir(src):
        inner = os.path.join(src, "validation")
        folder = inner if os.path.isdir(inner) else src
    else:
        if not os.path.isfile(src):
            raise SystemExit(f"cache_validation: table: {src}: no such folder or file")
        folder = os.path.join(os.path.dirname(os.path.abspath(src)), ".cache-validation-table")
        shutil.rmtree(folder, ignore_errors=True)
        try:
            with tarfile.open(src) as tar:
                if hasattr(tarfile, "data_filter"):
                    tar.extractall(folder, filter="data")
                else:
                    tar.extractall(folder)
        except tarfile.TarError as e:
            raise SystemExit(f"cache_validation: table: {src}: not a readable archive ({e})")
        folder = os.path.join(folder, "validation")
    if not os.path.isfile(os.path.join(folder, "manifest.json")):
        raise SystemExit(f"cache_validation: table: {src}: no manifest.json (not the render "
                         "phase's folder or validation.tgz)")
    return folder


def pct(v, signed=False):
    return f"{100 * v:+.1f} %" if signed else f"{100 * v:.1f} %"


def table(args):
    folder = load_folder(args.source)
    with open(os.path.join(folder, "manifest.json")) as f:
        manifest = json.load(f)
    rows, worst = [], None
    rows.append("| condition | blocks | cache: mean rel. error | p99 | bias | target | "
                "single scattering: mean rel. error | bias | reference: spp | noise per block | "
                "bake ms |")
    rows.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    items = [(n, c["label"], n, None) for n, c in manifest["conditions"].items()]
    for r in manifest.get("regions", []):
        if r["of"] not in manifest["conditions"]:
            continue  # a run of other conditions (--only)
        after = next(i for i, it in enumerate(items) if it[0] == r["of"]) + 1
        items.insert(after, (r["name"], r["label"], r["of"], r["above_background"]))
    results = {}
    for key, label, name, region in items:
        c = manifest["conditions"][name]
        paths = {k: os.path.join(folder, f) for k, f in
                 (("ref", f"ref-{name}.pfm"), ("se", f"ref-{name}-stderr.pfm"),
                  ("cache", f"gpu-{name}-cache.pfm"), ("single", f"gpu-{name}-single.pfm"))}
        missing = [k for k, p in paths.items() if not os.path.exists(p)]
        if "ref" in missing or "se" in missing or "cache" in missing:
            rows.append(f"| {label} | missing: {', '.join(missing)} |||||||||")
            continue
        w, h, ref = read_pfm(paths["ref"])
        _, _, se = read_pfm(paths["se"])
        ref_y, se_y = luminance(ref), luminance(se)
        stats = {}
        for k in ("cache", "single"):
            if k in missing:
                continue
            iw, ih, img = read_pfm(paths[k])
            if (iw, ih) != (w, h):
                raise SystemExit(f"cache_validation: {paths[k]} is {iw}x{ih}, the reference "
                                 f"{w}x{h}")
            stats[k] = compare(ref_y, se_y, luminance(img), w, h, c["background"], region)
        s = stats["cache"]
        if s is None:
            rows.append(f"| {label} | 0 |||||||||")
            continue
        results[key] = stats
        ss = stats.get("single")
        target = TARGET.get(name, 0.10)
        single = f"{ss['mean']:.3f} | {pct(ss['bias'], True)}" if ss else "- | -"
        bake = f"{c['bake_ms']:.0f}" if "bake_ms" in c else "-"
        rows.append(f"| {label} | {s['blocks']} | {s['mean']:.3f} | {s['p99']:.3f} | "
                    f"{pct(s['bias'], True)} | {target:.2f} | {single} | "
                    f"{c.get('ref_spp', '?')} | {s['noise']:.3f} | {bake} |")
        if worst is None or s["mean"] / target > worst[1] / worst[2]:
            worst = (label, s["mean"], target)
    text = "\n".join(rows) + "\n"
    if worst:
        over = [it[1] for it in items if it[0] in results and
                results[it[0]]["cache"]["mean"] > TARGET.get(it[2], 0.10)]
        text += (f"\nWorst (relative to its target): {worst[0]}, {worst[1]:.3f}. Above target: "
                 f"{'; '.join(over) if over else 'none'}. {manifest['size']}x{manifest['size']} "
                 f"pixels, blocks of {manifest['block']}x{manifest['block']}.\n")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    print(text, end="")
    return 0


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="phase", required=True)
    r = sub.add_parser("render")
    r.add_argument("--budget", type=float, help="seconds for the whole phase (400; quick 60)")
    r.add_argument("--noise", type=float, default=0.02,
                   help="the reference's target mean relative standard error per block")
    r.add_argument("--work", help="working folder (build/cache-validation)")
    r.add_argument("--out", help="where validation.tgz goes ($OUT, else the working folder)")
    r.add_argument("--bin", help="folder of veil-bench")
    r.add_argument("--only", help="comma-separated condition names")
    r.add_argument("--quick", action="store_true")
    t = sub.add_parser("table")
    t.add_argument("source", help="the render phase's folder or validation.tgz")
    t.add_argument("--out", help="markdown file")
    t.add_argument("--json", help="the numbers as JSON")
    args = p.parse_args(argv)
    return render(args) if args.phase == "render" else table(args)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
