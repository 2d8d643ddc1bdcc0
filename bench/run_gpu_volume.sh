#!/usr/bin/env bash
# `volume` shadows on the GPU (issue 11, 003 sec. 3.2), one device call. Here:
# tools/gpu-bundle (the workplace's) build/release/bench/veil-bench; there (carry .gpu):
# bash bench/run_gpu_volume.sh -> $OUT/volume-*.json and a table on stdout.
# Scene datasets/scenes/shadow-volumes-city.json (216 boxes, 112 spheres, the teapot, a floor:
# ~1.04 M triangles, one directional light) at 1920x1080. Per setting (none, culling = caster
# + receiver culling, clamping, both): the shadow passes' GPU time (GL_TIME_ELAPSED, median of
# 50 frames after 15 warm-up frames, `measure` off so that nothing else runs) and the stencil
# fill and volume triangles of one frame (`measure` on); `opaque` (2048^2 map) in the same run.
set -uo pipefail
[ -n "${GPU_FILES:-}" ] || source .gpu/env.sh # (already sourced when run from a bundle)
export VEIL_SHADER_DIR=$PWD/shaders
R=$OUT
S=datasets/scenes/shadow-volumes-city.json
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv > "$R/gpu.txt"
W=1920; H=1080
# Clocks ramp up during the first seconds of a call: a throwaway warm-up first.
veil-bench datasets/scenes/room.json --frames 300 --warmup 50 --width $W --height $H \
  > /dev/null 2>&1
run() { # tag frames measure caster receiver clamp
  timeout 100 veil-bench $S --width $W --height $H --set render.shadows.type=volume \
    --set render.shadows.measure=$3 --set render.shadows.caster_culling=$4 \
    --set render.shadows.receiver_culling=$5 --set render.shadows.clamping=$6 \
    --frames $2 --warmup 15 --json "$R/volume-$1.json" > /dev/null 2>> "$R/log.txt" ||
    echo "failed: $1" >> "$R/log.txt"
}
run none-fill 2 true false false false
run culling-fill 2 true true true false
run clamping-fill 2 true false false true
run both-fill 2 true true true true
for rep in a b; do
  run none-time-$rep 50 false false false false
  run culling-time-$rep 50 false true true false
  run clamping-time-$rep 50 false false false true
  run both-time-$rep 50 false true true true
  timeout 100 veil-bench $S --width $W --height $H --set render.shadows.type=opaque \
    --frames 50 --warmup 15 --json "$R/volume-opaque-time-$rep.json" > /dev/null 2>> "$R/log.txt"
done
cat "$R/log.txt" 2>/dev/null | tail -5
python3 - "$R" <<'PY'
import json, os, sys
R = sys.argv[1]
print(open(os.path.join(R, "gpu.txt")).read().strip())
def load(n):
    p = os.path.join(R, "volume-%s.json" % n)
    return json.load(open(p)) if os.path.exists(p) else None
def shadow_ms(d):
    return sum(p["median_ms"] for p in d["passes"] if p["name"].startswith("shadow"))
def pass_ms(d, name):
    return sum(p["median_ms"] for p in d["passes"] if p["name"] == name)
d0 = load("none-fill")
if d0: print("triangles", d0["triangles"])
base = {}
print("%-9s %-4s %9s %9s %9s %7s %12s %7s %10s %6s %7s" % ("setting", "rep", "shadow ms", "volume ms",
      "opaque ms", "t/none", "fill", "f/none", "vol tris", "culled", "clamped"))
for rep in "ab":
    n = load("none-time-" + rep)
    for s in ["none", "culling", "clamping", "both"]:
        d, f = load("%s-time-%s" % (s, rep)), load(s + "-fill")
        if not d or not f or not n: print(s, rep, "missing"); continue
        st = f["shadow_stats"]
        print("%-9s %-4s %9.3f %9.3f %9.3f %7.2f %12d %7.2f %10d %6d %7d" % (s, rep, shadow_ms(d),
              pass_ms(d, "shadow.volume"), pass_ms(d, "opaque"), shadow_ms(n) / shadow_ms(d),
              st["stencil_fragments"], d0["shadow_stats"]["stencil_fragments"] / max(st["stencil_fragments"], 1),
              st["volume_triangles"], st["culled"], st["clamped"]))
    o = load("opaque-time-" + rep)
    if o and n:
        print("%-9s %-4s %9.3f %9s %9.3f %7.2f   (opaque map 2048^2: shadow passes / none's)" % ("opaque",
              rep, shadow_ms(o), "-", pass_ms(o, "opaque"), shadow_ms(n) / shadow_ms(o)))
PY
