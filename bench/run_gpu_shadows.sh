#!/usr/bin/env bash
# Shadow techniques on the GPU (issue: shadows from everything that is not opaque), one device
# call. Here: tools/gpu-bundle (the workplace's) build/release/bench/veil-bench; there (carry
# .gpu): bash bench/run_gpu_shadows.sh -> $OUT/shadow-*.json and a table on stdout.
# Scenes fog.json and oit-foliage.json at 1920x1080, 2048^2 maps per light view; each
# technique's shadow passes and the receivers (opaque, fog, transparent), median of 120
# frames after 30 warm-up frames, GL_TIME_ELAPSED per pass; ratios to `opaque` in the same run.
set -uo pipefail
source .gpu/env.sh
R=$OUT
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv > "$R/gpu.txt"
W=1920; H=1080
run() { # tag scene oit shadow-type [extra --set ...]
  local tag=$1 scene=$2 oit=$3 type=$4; shift 4
  timeout 150 veil-bench datasets/scenes/$scene.json --oit $oit --width $W --height $H \
    --set render.shadows.type=$type --set render.shadows.size=2048 "$@" \
    --frames 120 --warmup 30 --json "$R/shadow-$tag.json" > /dev/null 2>> "$R/log.txt" ||
    echo "failed: $tag" >> "$R/log.txt"
}
# Clocks ramp up during the first seconds of a call: a throwaway warm-up first.
veil-bench datasets/scenes/room.json --frames 400 --warmup 50 --width $W --height $H \
  > /dev/null 2>&1
TECHS="opaque moment moment16 transmittance-slicemap stochastic stochastic-vsm"
for scene in fog oit-foliage; do
  oit=reference; [ $scene = oit-foliage ] && oit=blend
  for t in $TECHS; do
    if [ $t = moment16 ]; then run "$scene-$oit-$t" $scene $oit moment --set render.shadows.storage=quantized16
    else run "$scene-$oit-$t" $scene $oit $t; fi
  done
done
# The whole frame with moment shadows under every OIT technique (target <= 16 ms).
for oit in blend wboit moment-p4 moment-p6 moment-t3 stochastic phenomenological reference; do
  run "fog-$oit-moment-frame" fog $oit moment
done
python3 - "$R" <<'PY'
import json, glob, os, sys
R = sys.argv[1]
print(open(os.path.join(R, "gpu.txt")).read().strip())
runs = {}
for f in sorted(glob.glob(os.path.join(R, "shadow-*.json"))):
    d = json.load(open(f))
    runs[os.path.basename(f)[7:-5]] = d
def shadow_ms(d): return sum(p["median_ms"] for p in d["passes"] if p["name"].startswith("shadow"))
def recv_ms(d): return sum(p["median_ms"] for p in d["passes"] if p["name"] in ("opaque", "fog", "transparent"))
print(f"{'run':48s} {'shadow ms':>9s} {'recv ms':>8s} {'sum/opaque':>10s} {'frame ms':>9s}  passes")
for tag, d in runs.items():
    scene = tag.split("-")[0] if not tag.startswith("oit-foliage") else "oit-foliage"
    oit = d["oit"]
    base = runs.get(f"{scene}-{oit}-opaque")
    s, r = shadow_ms(d), recv_ms(d)
    ratio = (s + r) / (shadow_ms(base) + recv_ms(base)) if base else float("nan")
    passes = " ".join(f"{p['name']}={p['median_ms']:.3f}" for p in d["passes"])
    print(f"{tag:48s} {s:9.3f} {r:8.3f} {ratio:10.3f} {d['total_median_ms']:9.3f}  {passes}")
PY
tail -5 "$R/log.txt" 2>/dev/null
