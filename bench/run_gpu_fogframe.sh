#!/usr/bin/env bash
# Issue 14 item 1 (fog.json frame <= 8 ms): what bounds each pass of fog.json's blend frame,
# one device call. Here: tools/gpu-bundle build/release/bench/veil-bench shaders this script;
# there: bash $GPU_FILES/run_gpu_fogframe.sh -> table on stdout, per-case JSON in $OUT.
# 1920x1080, blend, 10 warm-up + 40 timed frames per case; each case changes one setting of
# fog.json (--set) so the pass it moves is attributed by ratio to `base` in the same call.
set -uo pipefail
[ -n "${GPU_FILES:-}" ] || source .gpu/env.sh
export VEIL_SHADER_DIR=${VEIL_SHADER_DIR:-$PWD/shaders}
R=${OUT:-/tmp/fogframe-out}; mkdir -p "$R"
W=${W:-1920}; H=${H:-1080}; FR=${FR:-40}; WU=${WU:-10}; WARM_S=${WARM_S:-20}
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv > "$R/gpu.txt" 2>/dev/null ||
  echo "no nvidia-smi" > "$R/gpu.txt"
run() { # tag [--set ...]
  local tag=$1; shift
  timeout 90 veil-bench datasets/scenes/fog.json --oit blend --width $W --height $H \
    --frames $FR --warmup $WU "$@" --json "$R/$tag.json" > /dev/null 2>> "$R/log.txt" ||
    echo "failed: $tag" >> "$R/log.txt"
}
end=$((SECONDS + WARM_S))
while [ $SECONDS -lt $end ]; do
  veil-bench datasets/scenes/room.json --width $W --height $H --frames 300 --warmup 0 \
    > /dev/null 2>&1
done
M='"type":"moment"'
run base
run shadow1024 --set "render.shadows={$M,\"size\":1024}"
run shadow512 --set "render.shadows={$M,\"size\":512}"
run blur0 --set "render.shadows={$M,\"size\":2048,\"blur_radius\":0}"
run media16 --set "render.shadows={$M,\"size\":2048,\"media_steps\":16}"
run quant16 --set "render.shadows={$M,\"size\":2048,\"storage\":\"quantized16\"}"
run opaqueshadow --set 'render.shadows={"type":"opaque","size":2048}'
run fogsteps80 --set render.fog_steps=80
run fogsteps40 --set render.fog_steps=40
run fogres2 --set render.fog_resolution=2
run base2
python3 - "$R" <<'PY'
import json, glob, os, sys
R = sys.argv[1]
print(open(os.path.join(R, "gpu.txt")).read().strip())
print("fog.json blend 1920x1080, pass medians (ms), 10 warm-up + 40 frames")
for f in sorted(glob.glob(os.path.join(R, "*.json")), key=os.path.getmtime):
    j = json.load(open(f))
    p = {x["name"]: x["median_ms"] for x in j["passes"]}
    print(f"{os.path.basename(f)[:-5]:14s} frame {j['total_median_ms']:7.3f}  " +
          "  ".join(f"{k} {v:.3f}" for k, v in p.items()))
PY
tail -8 "$R/log.txt" 2>/dev/null
