#!/usr/bin/env bash
# Fog benchmark only (device run, carry .gpu): see run_gpu.sh.
set -uo pipefail
source .gpu/env.sh
export VEIL_SHADER_DIR=$PWD/shaders
for r in 1 2 4; do
  for rep in a b; do
    veil-bench bench/scenes/cloud256.json --set render.fog_resolution=$r --width 1920 \
      --height 1080 --frames 60 --warmup 10 --json "$OUT/fog-cloud256-r$r-$rep.json" > /dev/null
  done
  veil-bench datasets/scenes/fog.json --set render.fog_resolution=$r --set render.fog_steps=128 \
    --width 1920 --height 1080 --frames 60 --warmup 10 --json "$OUT/fog-smoke-r$r.json" > /dev/null
done
python3 - "$OUT" <<'PY'
import json, glob, sys, os
for f in sorted(glob.glob(os.path.join(sys.argv[1], "fog-*.json"))):
    d = json.load(open(f))
    p = {x["name"]: x for x in d["passes"]}["fog"]
    print(os.path.basename(f), "fog median %.3f min %.3f max %.3f" % (p["median_ms"], p["min_ms"], p["max_ms"]))
PY
