#!/usr/bin/env bash
# Issue 14 item 1, before/after in one device call: "before" = main's veil-bench + shaders
# (veil-bench-before, shaders-before), "after" = branch fog-frame (moment maps cleared by
# compute). fog.json 1920x1080, 10 warm-up + 40 frames, two reps (a, b) for blend; every OIT
# technique after. Here: gpu-bundle <wt>/veil-bench <main>/veil-bench-before <wt>/shaders
# shaders-before this script.
set -uo pipefail
[ -n "${GPU_FILES:-}" ] || source .gpu/env.sh
R=${OUT:-/tmp/fogframe2-out}; mkdir -p "$R"
W=${W:-1920}; H=${H:-1080}; FR=${FR:-40}; WU=${WU:-10}; WARM_S=${WARM_S:-10}
run() { # build oit tag
  local exe=veil-bench sh=$GPU_FILES/shaders
  [ "$1" = before ] && exe=veil-bench-before sh=$GPU_FILES/shaders-before
  VEIL_SHADER_DIR=$sh timeout 90 $exe datasets/scenes/fog.json --oit $2 --width $W --height $H \
    --frames $FR --warmup $WU --json "$R/$1.$3.json" > /dev/null 2>> "$R/log.txt" ||
    echo "failed: $1 $3" >> "$R/log.txt"
}
end=$((SECONDS + WARM_S))
while [ $SECONDS -lt $end ]; do
  VEIL_SHADER_DIR=$GPU_FILES/shaders veil-bench datasets/scenes/room.json --width $W --height $H \
    --frames 300 --warmup 0 > /dev/null 2>&1
done
for rep in a b; do run before blend blend-$rep; run after blend blend-$rep; done
for t in wboit phenomenological moment-p6 moment-p6-16 moment-p6-half stochastic-depth reference; do
  run before $t $t; run after $t $t
done
python3 - "$R" <<'PY'
import json, glob, os, sys
R = sys.argv[1]
print("fog.json 1920x1080, frame = sum of pass medians (ms), 10 warm-up + 40 frames")
for f in sorted(glob.glob(os.path.join(R, "*.json")), key=os.path.getmtime):
    j = json.load(open(f))
    p = {x["name"]: x["median_ms"] for x in j["passes"]}
    print(f"{os.path.basename(f)[:-5]:26s} frame {j['total_median_ms']:7.3f}  " +
          "  ".join(f"{k} {v:.3f}" for k, v in p.items() if k != "resolve"))
PY
tail -5 "$R/log.txt" 2>/dev/null
