#!/usr/bin/env python3
"""veil-bench --light-drag / --converge (bench/scattered_light_bench.h) on a small slab whose
scattered-light cache is baked on the GPU (1445 texels), against what the
progressive bake must do:

  - a budget too small for more than one path per texel per frame and no frame time to fill
    (512 paths): every drag frame restarts
    the bake (the last frame's bake is 1/512 done), the cache is off its converged value right
    after the drag and the error shrinks as paths come in; where the bake is done the error is
    0 exactly (the converged cache is the same bake run to its end);
  - a budget of 100 ms, or frames of 1000 ms to fill, and 8 paths (the whole bake fits one
    frame): 0 at every time;
  - a scene without the cache is refused with one line naming --light-drag.

Usage: light_drag_bench.py VEIL_BENCH [REPO_ROOT]. Standard library only; a few seconds on
llvmpipe.
"""
import json
import os
import sys
import tempfile

from bench_run import check, failures, run_bench

BENCH = os.path.abspath(sys.argv[1])
ROOT = os.path.abspath(sys.argv[2] if len(sys.argv) > 2 else
                       os.path.join(os.path.dirname(__file__), "..", ".."))
os.environ.setdefault("VEIL_SHADER_DIR", os.path.join(ROOT, "shaders"))

SLAB = {
    "render": {"width": 16, "height": 16, "ambient": [0.1, 0.1, 0.1], "background": [0, 0, 0],
               "fog_steps": 32, "fog_scattered_light": True,
               "fog_scattered_light_samples": 64, "fog_scattered_light_cell": 2,
               "fog_scattered_light_bake": "gpu"},
    "cameras": [{"name": "c", "type": "orthographic", "position": [0, 4, 0.01],
                 "target": [0, 0, 0], "ortho_height": 2, "near": 0.5, "far": 20}],
    "lights": [{"type": "directional", "direction": [0.3, -1, 0.2], "intensity": 1}],
    "volumes": [{"procedural": "box", "size": [2, 0.5, 2], "voxel_size": 0.0625,
                 "density_scale": 4, "albedo": 0.9, "anisotropy": 0.3}]}


def drag(scene, *extra):
    out = os.path.join(os.path.dirname(scene), "drag.json")
    cmd = [BENCH, scene, "--width", "16", "--height", "16", "--frames", "3", "--warmup", "0",
           "--light-drag", "20", "--converge", "--json", out] + list(extra)
    return run_bench(cmd, out, ROOT, 120)


with tempfile.TemporaryDirectory() as tmp:
    scene = os.path.join(tmp, "slab.json")
    with open(scene, "w") as f:
        json.dump(SLAB, f)

    # One path per texel per frame: 0.001 ms buys one dispatch, one sample over all texels
    # (frame_ms 0: the budget alone); 512 paths, so that the bake outlasts several of the
    # times after the drag however fast the frames are.
    r, p = drag(scene, "--set", "render.fog_scattered_light_budget_ms=0.001",
                "--set", "render.fog_scattered_light_frame_ms=0",
                "--set", "render.fog_scattered_light_samples=512")
    check(r is not None, "small budget runs" + ("" if r else f": {p.stderr[-500:]}"))
    if r:
        check(abs(r["drag_fraction_per_frame"] - 1 / 512) < 1e-9,
              f"each drag frame restarts the bake: 1/512 done ({r['drag_fraction_per_frame']})")
        rows = r["convergence"]
        first = rows[0]
        check(first["bake_fraction"] < 1 and first["cache_rel_l1"] > 0.02,
              f"right after the drag the cache is off ({first['cache_rel_l1']:.3f} at "
              f"{first['bake_fraction']:.3f} done)")
        unfinished = [x for x in rows if x["bake_fraction"] < 1]
        check(all(a["cache_rel_l1"] >= b["cache_rel_l1"]
                  for a, b in zip(unfinished, unfinished[1:])) and len(unfinished) >= 2,
              "the error shrinks as paths come in: "
              + ", ".join(f"{x['cache_rel_l1']:.3f}" for x in unfinished))
        done = [x for x in rows if x["bake_fraction"] >= 1]
        check(all(x["cache_rel_l1"] == 0 and x["frame_rel_l1"] == 0 for x in done),
              f"0 where the bake is done ({len(done)} of {len(rows)} times)")
        names = {q["name"]: q["median_ms"] for q in r["passes"]}
        check(abs(names.get("cache_error_pct_1.00s", -1) - 100 * rows[3]["cache_rel_l1"]) < 1e-9,
              "pseudo-pass cache_error_pct_1.00s = 100 x the error at 1 s")
        check(abs(r["drag_fps"] * names["frame_wall"] - 1000) < 1e-6, "drag_fps = 1000 / frame_wall")

    for what, options in (("a budget", ["render.fog_scattered_light_budget_ms=100"]),
                          ("a frame time", ["render.fog_scattered_light_budget_ms=0.001",
                                            "render.fog_scattered_light_frame_ms=1000"])):
        r, p = drag(scene, *[a for o in options for a in ("--set", o)],
                    "--set", "render.fog_scattered_light_samples=8")
        check(r is not None and r["drag_fraction_per_frame"] == 1 and
              all(x["cache_rel_l1"] == 0 for x in r["convergence"]),
              f"{what} that fits the whole bake: converged every frame"
              + (f" ({r['drag_fraction_per_frame']}, "
                 + ", ".join(f"{x['cache_rel_l1']:.3f}" for x in r["convergence"]) + ")"
                 if r else f": {p.stderr[-300:]}"))

    plain = dict(SLAB, render=dict(SLAB["render"], fog_scattered_light=False))
    with open(scene, "w") as f:
        json.dump(plain, f)
    r, p = drag(scene)
    check(r is None and p.returncode != 0 and "--light-drag" in p.stderr and
          len(p.stderr.strip().splitlines()) == 1,
          "a scene without the cache is refused in one line: " + p.stderr.strip()[-200:])

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all checks passed")
