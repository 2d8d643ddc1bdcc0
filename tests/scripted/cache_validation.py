#!/usr/bin/env python3
"""scripts/cache_validation.py and the veil-bench modes it runs, against numbers they did not
produce:

  - veil-bench --pfm (the GPU frame's linear radiance) against veil-bench --pathtraced on an
    absorbing box off the view's centre (albedo 0: both compute background x exp(-tau)), per
    pixel within 5 standard errors + 3 %; the frame flipped upside down fails (the two images
    must agree in orientation, or every block comparison is meaningless);
  - veil-bench --surface-pathtraced on a floor in a corner of the view under a sky, no volume
    above it: base colour x ambient exactly (E = pi x ambient), on the pixels where the GPU
    frame (no cache: the ambient term alone) shows the floor;
  - the table phase on synthetic images whose statistics are known: mean relative error over
    4x4 blocks 0.10, p99, bias, the reference's noise per block 0.02, the region row;
  - merging reference chunks: the spp-weighted mean and its standard error.

Usage: cache_validation.py VEIL_BENCH [REPO_ROOT]. Standard library only; about 20 s on llvmpipe.
"""
import json
import math
import os
import subprocess
import sys
import tempfile

BENCH = os.path.abspath(sys.argv[1])
ROOT = os.path.abspath(sys.argv[2] if len(sys.argv) > 2 else
                       os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import cache_validation as cv  # noqa: E402

failures = []
os.environ.setdefault("VEIL_SHADER_DIR", os.path.join(ROOT, "shaders"))


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


work = tempfile.mkdtemp(prefix="veil-cache-validation.")
N = 16


def scene(doc, name):
    path = os.path.join(work, name)
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def bench(*args):
    subprocess.run([BENCH, *args, "--width", str(N), "--height", str(N)], check=True,
                   stdout=subprocess.DEVNULL)


# An absorbing box (tau 1.2 through its depth) in the view's upper left, a bright background.
box = scene({
    "render": {"width": N, "height": N, "background": [0.8, 0.6, 0.4], "ambient": 0,
               "fog_steps": 128, "fog_jitter": False, "tonemap": "clamp", "oit": "blend"},
    "cameras": [{"name": "o", "type": "orthographic", "position": [0, 0, 5], "target": [0, 0, 0],
                 "ortho_height": 2, "near": 1, "far": 10}],
    "volumes": [{"name": "box", "procedural": "box", "size": [0.8, 0.8, 0.8], "voxel_size": 0.05,
                 "density_scale": 1.5, "albedo": 0.0,
                 "transform": {"translate": [-0.45, 0.45, 0]}}]}, "box.json")
gpu_pfm, pt_pfm = os.path.join(work, "gpu.pfm"), os.path.join(work, "pt.pfm")
bench(box, "--frames", "1", "--warmup", "0", "--pfm", gpu_pfm)
bench(box, "--pathtraced", "256", "3", pt_pfm)
_, _, gpu = cv.read_pfm(gpu_pfm)
_, _, pt = cv.read_pfm(pt_pfm)
_, _, se = cv.read_pfm(pt_pfm[:-4] + "-stderr.pfm")
gy, py, sy = cv.luminance(gpu), cv.luminance(pt), cv.luminance(se)


def agree(img):
    return sum(abs(a - b) > 5 * s + 0.03 * b for a, b, s in zip(img, py, sy))


flipped = [v for y in range(N - 1, -1, -1) for v in gy[y * N:(y + 1) * N]]
dark = sum(v < 0.9 * max(py) for v in py)
check(20 < dark < N * N // 2, f"the box darkens a part of the reference ({dark} pixels)")
check(agree(gy) == 0, f"--pfm frame = --pathtraced per pixel ({agree(gy)} pixels differ)")
check(agree(flipped) > 10, f"the frame flipped differs ({agree(flipped)} pixels)")

# A floor (base colour 0.5) in the view's upper left quarter under a sky; the box below it, out of view.
floor_doc = {
    "render": {"width": N, "height": N, "background": [0, 0, 0], "ambient": [0.2, 0.3, 0.4],
               "tonemap": "clamp", "oit": "blend", "shadows": "opaque"},
    "cameras": [{"name": "down", "type": "orthographic", "position": [0, 1, 0],
                 "target": [0, 0, 0], "up": [0, 0, -1], "ortho_height": 2, "near": 0.1,
                 "far": 5}],
    "materials": {"floor": {"base_color": 0.5, "roughness": 1}},
    "objects": [{"name": "floor", "shape": {"type": "plane", "size": [1, 1]},
                 "material": "floor", "transform": {"translate": [-0.5, 0, -0.5]}}],
    "volumes": [{"name": "box", "procedural": "box", "size": [0.5, 0.5, 0.5], "voxel_size": 0.1,
                 "density_scale": 1, "albedo": 0.5, "transform": {"translate": [4, -2, 0]}}]}
floor = scene(floor_doc, "floor.json")
fl_gpu, fl_pt = os.path.join(work, "floor-gpu.pfm"), os.path.join(work, "floor-pt.pfm")
bench(floor, "--frames", "1", "--warmup", "0", "--pfm", fl_gpu)
bench(floor, "--surface-pathtraced", "4", "1", fl_pt)
_, _, fg = cv.read_pfm(fl_gpu)
_, _, fp = cv.read_pfm(fl_pt)
on = [i for i in range(N * N) if fg[3 * i + 1] > 0.01]
corner = sum(1 for i in on if i % N < N // 2 and i // N < N // 2)
check(len(on) == N * N // 4 and corner == len(on),
      f"the GPU frame's floor is the upper left quarter ({len(on)} pixels, {corner} there)")
expected = [0.5 * a for a in floor_doc["render"]["ambient"]]
bad = [i for i in range(N * N)
       if any(abs(fp[3 * i + c] - (expected[c] if i in on else 0.0)) > 1e-4 for c in range(3))]
check(not bad, f"--surface-pathtraced = base colour x ambient on the floor, 0 off it "
               f"({len(bad)} pixels differ; pixel 0 {list(fp[0:3])})")

# The table on synthetic images: 32x32, background 0.9 (grey), the volume's blocks the left
# half (reference 1, its 4x4 blocks' se 0.02: per pixel 0.08), a rim of blocks at 3 (> 1.2x);
# the cache 1.1x on half of the volume's blocks and 0.9x on the other half (error 0.10, bias 0
# where the blocks are equal); single scattering 0.5x.
S = 32
syn = os.path.join(work, "syn")
os.makedirs(syn)
bg = 0.9


def img(f):
    out = []
    for y in range(S):
        for x in range(S):
            v = f(x, y)
            out += [v, v, v]
    return out


def ref(x, y):
    return (3.0 if y < 4 else 1.0) if x < S // 2 else bg


def cache(x, y):
    return ref(x, y) * ((1.1 if (x // 4 + y // 4) % 2 == 0 else 0.9) if x < S // 2 else 1.0)


for name, f in (("ref-c", ref), ("ref-c-stderr", lambda x, y: 0.08 * ref(x, y)),
                ("gpu-c-cache", cache), ("gpu-c-single", lambda x, y: 0.5 * ref(x, y))):
    cv.write_pfm(os.path.join(syn, name + ".pfm"), S, S, img(f))
with open(os.path.join(syn, "manifest.json"), "w") as f:
    json.dump({"size": S, "block": 4, "conditions": {"c": {"label": "synthetic",
               "background": [bg] * 3, "ref_spp": 64}},
               "regions": [{"name": "c-rim", "label": "rim", "of": "c",
                            "above_background": 1.2}]}, f)
out_json = os.path.join(work, "table.json")
subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "cache_validation.py"), "table",
                syn, "--json", out_json, "--out", os.path.join(work, "table.md")], check=True,
               stdout=subprocess.DEVNULL)
with open(out_json) as f:
    t = json.load(f)
c, s, rim = t["c"]["cache"], t["c"]["single"], t["c-rim"]["cache"]
check(c["blocks"] == 32 and abs(c["mean"] - 0.10) < 1e-6 and abs(c["p99"] - 0.10) < 1e-6,
      f"cache: 32 blocks, mean relative error 0.10, p99 0.10 ({c})")
# The bias: the rim's 4 blocks (3 x (2 x 1.1 + 2 x 0.9)) and 28 (14 x 1.1 + 14 x 0.9): 0.
check(abs(c["bias"]) < 1e-6 and abs(c["noise"] - 0.02) < 1e-6,
      f"cache: bias 0, reference noise per block 0.02 ({c['bias']}, {c['noise']})")
check(abs(s["mean"] - 0.5) < 1e-6 and abs(s["bias"] + 0.5) < 1e-6,
      f"single scattering: 0.5 and -50 % ({s['mean']}, {s['bias']})")
check(rim["blocks"] == 4 and abs(rim["ref_mean_y"] - 3.0) < 1e-5,
      f"the rim row: the 4 blocks above 1.2x the background ({rim['blocks']})")

# Merging chunks: 16 spp of mean 1 (se 0.1) and 48 of mean 2 (se 0.05).
mw = os.path.join(work, "merge")
os.makedirs(mw)
for seed, spp, m, e in ((1001, 16, 1.0, 0.1), (1002, 48, 2.0, 0.05)):
    stem = os.path.join(mw, f"ref-shipped-s{seed}-{spp}")
    cv.write_pfm(stem + ".pfm", 4, 4, [m] * 48)
    cv.write_pfm(stem + "-stderr.pfm", 4, 4, [e] * 48)
    with open(stem + ".json", "w") as f:
        json.dump({"seconds": 1.0}, f)
total, seconds, noise = cv.merge(mw, "shipped")
_, _, mm = cv.read_pfm(os.path.join(mw, "ref-shipped.pfm"))
_, _, me = cv.read_pfm(os.path.join(mw, "ref-shipped-stderr.pfm"))
want_e = math.hypot(0.25 * 0.1, 0.75 * 0.05)
check(total == 64 and abs(mm[0] - 1.75) < 1e-6 and abs(me[0] - want_e) < 1e-6,
      f"merge: 64 spp, mean 1.75, se {want_e:.5f} ({total}, {mm[0]}, {me[0]})")

print(f"{len(failures)} failure(s)" if failures else "all passed")
sys.exit(1 if failures else 0)
