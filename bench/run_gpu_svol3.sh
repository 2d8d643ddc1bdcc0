#!/usr/bin/env bash
# `volume` shadows after classify.comp's rework (each caster's footprint split over groups of
# 1024 columns, global atomic maxima, a finish pass), one device call; the pattern and settings
# of run_gpu_svol2.sh, trimmed to fit 200 s. Here: tools/gpu-bundle (the workplace's)
# build/release/bench/veil-bench, shaders/ and this script; there (carry .gpu):
# bash $GPU_FILES/run_gpu_svol3.sh -> $OUT/svol-*.json and tables on stdout.
# Scene datasets/scenes/shadow-volumes-city.json (1.02 M triangles, one directional light) at
# 1920x1080, zpass on. Per setting (none, culling = caster + receiver culling, clamping, both):
# the shadow passes' GPU time (GL_TIME_ELAPSED, median of 50 frames after 15 warm-up frames,
# `measure` off), the culled / clamped counts of one frame (`measure` on), and the pass's parts
# (GL_TIMESTAMP, `timing` on, last of 20 frames; classify is split into receivers, occluders
# and classify.comp).
set -uo pipefail
[ -n "${GPU_FILES:-}" ] || source .gpu/env.sh # (already sourced when run from a bundle)
export VEIL_SHADER_DIR=${VEIL_SHADER_DIR:-$PWD/shaders}
R=${OUT:-/tmp/svol-out}; mkdir -p "$R"
S=datasets/scenes/shadow-volumes-city.json
W=${W:-1920}; H=${H:-1080}; N=${N:-50}
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv > "$R/gpu.txt" 2>&1
# Clocks ramp up during the first seconds of a call: a throwaway warm-up first.
timeout 40 veil-bench datasets/scenes/room.json --frames 300 --warmup 50 --width $W --height $H \
  > /dev/null 2>&1
run() { # tag frames measure timing caster receiver clamp
  timeout 40 veil-bench $S --width $W --height $H --set render.shadows.type=volume \
    --set render.shadows.measure=$3 --set render.shadows.timing=$4 \
    --set render.shadows.caster_culling=$5 --set render.shadows.receiver_culling=$6 \
    --set render.shadows.clamping=$7 --frames $2 --warmup 15 --json "$R/svol-$1.json" \
    > /dev/null 2>> "$R/log.txt" || echo "failed: $1" >> "$R/log.txt"
}
for s in "none false false false" "culling true true false" "clamping false false true" \
  "both true true true"; do
  set -- $s
  run $1-parts 20 false true $2 $3 $4
  run $1-time $N false false $2 $3 $4
  run $1-fill 2 true false $2 $3 $4
done
grep -v "not a closed" "$R/log.txt" 2>/dev/null | tail -5
python3 - "$R" <<'PY'
import json, os, sys
R = sys.argv[1]
print(open(os.path.join(R, "gpu.txt")).read().strip())
def load(n):
    p = os.path.join(R, "svol-%s.json" % n)
    return json.load(open(p)) if os.path.exists(p) else None
def pass_ms(d, name):
    return sum(p["median_ms"] for p in d["passes"] if p["name"] == name)
n = load("none-time")
print("%-9s %9s %9s %7s %11s %6s %7s" % ("setting", "volume ms", "map ms", "t/none", "fill",
      "culled", "clamped"))
for s in ["none", "culling", "clamping", "both"]:
    d, f = load(s + "-time"), load(s + "-fill")
    if not d or not f or not n: continue
    st = f["shadow_stats"]
    print("%-9s %9.3f %9.3f %7.2f %11d %6d %7d" % (s, pass_ms(d, "shadow.volume"),
          pass_ms(d, "shadow"), pass_ms(n, "shadow.volume") / pass_ms(d, "shadow.volume"),
          st["stencil_fragments"], st["culled"], st["clamped"]))
print("\nparts of shadow.volume (ms, GL_TIMESTAMP, last frame of 20, timing on)")
for s in ["none", "culling", "clamping", "both"]:
    d = load(s + "-parts")
    if d: print("%-9s" % s, " ".join("%s %.3f" % kv for kv in d["shadow_stats"].get("part_ms", {}).items()))
PY
