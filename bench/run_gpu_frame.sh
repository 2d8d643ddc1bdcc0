#!/usr/bin/env bash
# Frame times before and after a change, in one device call (issue 9: "no pass slower by more
# than 2%"). Here:
#   cp <old build>/bench/veil-bench /tmp/vb/veil-bench-before; cp -r <old tree>/shaders /tmp/shaders-before
#   <workplace shared>/tools/gpu-bundle build/release/bench/veil-bench /tmp/vb/veil-bench-before \
#       /tmp/shaders-before   (the bundling tool, run here; the scenes come from the repo)
# There (device run, carry .gpu): bash bench/run_gpu_frame.sh  -> $OUT/frame-*.json, a table
set -uo pipefail
source .gpu/env.sh
R=$OUT
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv > "$R/gpu.txt"
W=1920; H=1080
run() { # build scene oit rep
  local exe=veil-bench shaders=$PWD/shaders
  [ "$1" = before ] && exe=veil-bench-before shaders=$GPU_FILES/shaders-before
  VEIL_SHADER_DIR=$shaders timeout 120 $exe datasets/scenes/$2.json --oit $3 --width $W --height $H \
    --frames 120 --warmup 30 --json "$R/frame-$2-$3-$1-$4.json" > /dev/null 2>> "$R/log.txt" ||
    echo "failed: $*" >> "$R/log.txt"
}
# Clocks ramp up during the first seconds of a call: a throwaway warm-up first.
VEIL_SHADER_DIR=$PWD/shaders veil-bench datasets/scenes/room.json --frames 400 --warmup 50 \
  --width $W --height $H > /dev/null 2>&1
for rep in 1 2; do
  for scene in default fog; do
    for t in blend wboit moment-p6 reference; do
      if [ $rep = 1 ]; then run before $scene $t $rep; run after $scene $t $rep;
      else run after $scene $t $rep; run before $scene $t $rep; fi
    done
  done
done
python3 - "$R" <<'PY'
import json, glob, os, sys
R = sys.argv[1]
print(open(os.path.join(R, "gpu.txt")).read().strip())
rows = {}
for f in glob.glob(os.path.join(R, "frame-*.json")):
    scene, oit_build_rep = os.path.basename(f)[6:-5].split("-", 1)
    *oit, build, rep = oit_build_rep.split("-")
    d = json.load(open(f))
    for p in d["passes"]:
        rows.setdefault((scene, "-".join(oit), p["name"]), {}).setdefault(build, []).append(p["median_ms"])
print(f"{'scene':8s} {'oit':10s} {'pass':12s} {'before ms':>10s} {'after ms':>10s} {'after/before':>12s}")
for (scene, oit, name), v in sorted(rows.items()):
    b = min(v.get("before", [float("nan")])); a = min(v.get("after", [float("nan")]))
    print(f"{scene:8s} {oit:10s} {name:12s} {b:10.3f} {a:10.3f} {a / b if b else 0:12.3f}")
PY
tail -5 "$R/log.txt" 2>/dev/null
