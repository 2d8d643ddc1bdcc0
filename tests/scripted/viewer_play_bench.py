#!/usr/bin/env python3
"""veil-bench --viewer-play (bench/viewer_play_bench.h): the viewer's timeline played without a
window over the EmberGen fire frames 1-4 (40x32), against what the timeline must do:

  - every frame of the range is shown in turn (frames_replaced counts the shows), each
    replacing the renderer's volumes rather than rebuilding it;
  - scrubbing back over frames just played takes them from the frames held on the GPU: no
    volume upload, one reshown frame per step (render.sequence_gpu_cache_mib); with the budget
    0 every step uploads;
  - the JSON's play_frame is the loop's wall clock per frame and fps its inverse;
  - a scene without a frame range is refused in one line naming --viewer-play.

Usage: viewer_play_bench.py VEIL_BENCH [REPO_ROOT]. Standard library only; seconds on llvmpipe.
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
FIRE = os.path.join(ROOT, "datasets", "third_party", "vdb-embergen-fire-seq",
                    "embergen_fire_a_#.vdb")

SCENE = {
    "render": {"width": 40, "height": 32, "fog_steps": 24},
    "time": {"frame_range": [1, 4]},
    "cameras": [{"position": [0, -62, -98], "target": [0, 0, -112], "up": [0, 0, 1]}],
    "lights": [{"type": "directional", "direction": [-0.4, 0.5, -0.75]}],
    "volumes": [{"name": "fire", "path": FIRE, "grid": "flames", "density_scale": 6.0,
                 "temperature_grid": "temperature", "temperature_scale": 1100,
                 "temperature_offset": 900}]}


def play(scene, *extra):
    out = os.path.join(os.path.dirname(scene), "play.json")
    cmd = [BENCH, scene, "--width", "40", "--height", "32", "--frames", "6", "--warmup", "1",
           "--viewer-play", "--scrub-back", "3", "--json", out] + list(extra)
    return run_bench(cmd, out, ROOT, 240)


with tempfile.TemporaryDirectory() as tmp:
    scene = os.path.join(tmp, "fire.json")
    with open(scene, "w") as f:
        json.dump(SCENE, f)

    r, p = play(scene)
    check(r is not None, "plays" + ("" if r else f": {p.stderr[-500:]}"))
    if r:
        check(r["range"] == [1, 4, 1], f"the scene's range 1-4 ({r['range']})")
        # 1 warm-up + 6 played + 3 scrubbed frames, each shown by replacing the volumes.
        check(r["frames_replaced"] == 10, f"every frame shown in turn ({r['frames_replaced']})")
        play_ = r["play"]
        check(play_["frames"] == 6 and abs(play_["fps"] * play_["ms_per_frame"] - 1000) < 1e-6,
              f"fps = 1000 / ms per frame ({play_})")
        names = {q["name"]: q["median_ms"] for q in r["passes"]}
        check(abs(names["play_frame"] - play_["ms_per_frame"]) < 1e-9,
              "play_frame is the loop's ms per frame")
        scrub = r["scrub_back"]
        check(scrub["frames"] == 3 and scrub["volume_uploads"] == 0 and
              scrub["volume_frames_reshown"] == 3,
              f"scrubbing back shows frames held on the GPU without an upload ({scrub})")

    r, p = play(scene, "--set", "render.sequence_gpu_cache_mib=0")
    check(r is not None and r["scrub_back"]["volume_uploads"] == 3 and
          r["scrub_back"]["volume_frames_reshown"] == 0,
          "no frames held: every scrubbed frame uploads"
          + (f" ({r['scrub_back']})" if r else f": {p.stderr[-300:]}"))

    still = dict(SCENE)
    still.pop("time")
    still["volumes"] = [dict(SCENE["volumes"][0], path=FIRE.replace("#", "1"))]
    with open(scene, "w") as f:
        json.dump(still, f)
    r, p = play(scene)
    check(r is None and p.returncode != 0 and "--viewer-play" in p.stderr and
          len(p.stderr.strip().splitlines()) == 1,
          "a scene without a frame range is refused in one line: " + p.stderr.strip()[:200])

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
