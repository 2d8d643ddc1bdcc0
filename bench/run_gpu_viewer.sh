#!/usr/bin/env bash
# The viewer's frame path (veil-bench --viewer: ViewSession::renderFrame without a window) on
# datasets/scenes/fog.json at 1920x1080, one device call (carry .gpu from
# `gpu-bundle build/release/bench/veil-bench`). Warm-up case first (clocks ramp up).
set -uo pipefail
source .gpu/env.sh
export VEIL_SHADER_DIR=$PWD/shaders
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
timeout 40 veil-bench datasets/scenes/fog.json --width 1920 --height 1080 --frames 60 --warmup 30 \
  > /dev/null 2>&1
timeout 60 veil-bench datasets/scenes/fog.json --viewer --width 1920 --height 1080 --frames 100 \
  --warmup 30 --json "$OUT/viewer-fog-1080p.json" > /dev/null 2> "$OUT/log.txt"
echo "rc $?"
python3 - "$OUT/viewer-fog-1080p.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(d["renderer"], d["width"], "x", d["height"], "oit", d["oit"], "shadows", d["shadows"])
for p in d["passes"]:
    print("  %-20s %8.3f ms" % (p["name"], p["median_ms"]))
for k in ("gpu_total_median_ms", "viewer_frame_wall_median_ms", "renderer_frame_wall_median_ms",
          "viewer_over_renderer"):
    print("%-32s %.3f" % (k, d[k]))
for k, v in d["edits"].items():
    print("edit %-28s %s" % (k, v))
PY
