#!/usr/bin/env bash
# `volume` shadows on the GPU after issue 11's rework (compute silhouettes drawn indirectly,
# culled casters never launched, silhouette-fan back caps, depth-pass where the eye is outside),
# one device call. Here: tools/gpu-bundle (the workplace's) build/release/bench/veil-bench,
# shaders/ and this script; there (carry .gpu): bash $GPU_FILES/run_gpu_svol2.sh ->
# $OUT/svol-*.json and tables on stdout.
# Scene datasets/scenes/shadow-volumes-city.json (216 boxes, 112 spheres, the teapot, a floor:
# 1.02 M triangles, one directional light) at 1920x1080. Per setting (none, culling = caster +
# receiver culling, clamping, both; zpass on unless named): the shadow passes' GPU time
# (GL_TIME_ELAPSED, median of 50 frames after 15 warm-up frames, `measure` off), the stencil
# fill, volume triangles and pipeline statistics of one frame (`measure` on), and the pass's
# parts (GL_TIMESTAMP, `timing` on, last of 20 frames); `opaque` (2048^2 map) in the same run.
set -uo pipefail
[ -n "${GPU_FILES:-}" ] || source .gpu/env.sh # (already sourced when run from a bundle)
export VEIL_SHADER_DIR=${VEIL_SHADER_DIR:-$PWD/shaders}
R=${OUT:-/tmp/svol-out}; mkdir -p "$R"
S=datasets/scenes/shadow-volumes-city.json
W=${W:-1920}; H=${H:-1080}; N=${N:-50}
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv > "$R/gpu.txt" 2>&1
# Clocks ramp up during the first seconds of a call: a throwaway warm-up first.
timeout 60 veil-bench datasets/scenes/room.json --frames 300 --warmup 50 --width $W --height $H \
  > /dev/null 2>&1
run() { # tag frames measure timing zpass caster receiver clamp
  timeout 60 veil-bench $S --width $W --height $H --set render.shadows.type=volume \
    --set render.shadows.measure=$3 --set render.shadows.timing=$4 --set render.shadows.zpass=$5 \
    --set render.shadows.caster_culling=$6 --set render.shadows.receiver_culling=$7 \
    --set render.shadows.clamping=$8 --frames $2 --warmup 15 --json "$R/svol-$1.json" \
    > /dev/null 2>> "$R/log.txt" || echo "failed: $1" >> "$R/log.txt"
}
run none-fill 2 true false true false false false
run culling-fill 2 true false true true true false
run clamping-fill 2 true false true false false true
run both-fill 2 true false true true true true
run both-zfail-fill 2 true false false true true true
run none-zfail-fill 2 true false false false false false
for rep in a b; do
  run none-time-$rep $N false false true false false false
  run culling-time-$rep $N false false true true true false
  run clamping-time-$rep $N false false true false false true
  run both-time-$rep $N false false true true true true
  timeout 60 veil-bench $S --width $W --height $H --set render.shadows.type=opaque \
    --frames $N --warmup 15 --json "$R/svol-opaque-time-$rep.json" > /dev/null 2>> "$R/log.txt"
done
run none-zfail-time-a $N false false false false false false
run both-zfail-time-a $N false false false true true true
run none-parts 20 false true true false false false
run both-parts 20 false true true true true true
run none-zfail-parts 20 false true false false false false
grep -v "not a closed" "$R/log.txt" 2>/dev/null | tail -5
python3 - "$R" <<'PY'
import json, os, sys
R = sys.argv[1]
print(open(os.path.join(R, "gpu.txt")).read().strip())
def load(n):
    p = os.path.join(R, "svol-%s.json" % n)
    return json.load(open(p)) if os.path.exists(p) else None
def shadow_ms(d):
    return sum(p["median_ms"] for p in d["passes"] if p["name"].startswith("shadow"))
def pass_ms(d, name):
    return sum(p["median_ms"] for p in d["passes"] if p["name"] == name)
d0 = load("none-fill")
if d0: print("triangles", d0["triangles"])
print("%-13s %-3s %9s %9s %7s %7s %11s %6s %9s %9s %6s %7s" % ("setting", "rep", "shadow ms",
      "volume ms", "map ms", "t/none", "fill", "f/none", "vol tris", "submitted", "culled", "clamped"))
for rep in "ab":
    n = load("none-time-" + rep)
    for s in ["none", "culling", "clamping", "both", "none-zfail", "both-zfail"]:
        d, f = load("%s-time-%s" % (s, rep)), load(s + "-fill")
        if not d or not f or not n: continue
        st = f["shadow_stats"]
        print("%-13s %-3s %9.3f %9.3f %7.3f %7.2f %11d %6.2f %9d %9d %6d %7d" % (s, rep,
              shadow_ms(d), pass_ms(d, "shadow.volume"), pass_ms(d, "shadow"),
              pass_ms(n, "shadow.volume") / pass_ms(d, "shadow.volume"), st["stencil_fragments"],
              d0["shadow_stats"]["stencil_fragments"] / max(st["stencil_fragments"], 1),
              st["volume_triangles"], st["submitted_triangles"], st["culled"], st["clamped"]))
    o = load("opaque-time-" + rep)
    if o and n:
        print("%-13s %-3s %9.3f %9s %7.3f   (opaque map 2048^2: shadow passes)" % ("opaque",
              rep, shadow_ms(o), "-", pass_ms(o, "shadow")))
print("\nparts of shadow.volume (ms, GL_TIMESTAMP, last frame of 20, timing on)")
for s in ["none-parts", "both-parts", "none-zfail-parts"]:
    d = load(s)
    if d: print("%-17s" % s, " ".join("%s %.3f" % kv for kv in d["shadow_stats"].get("part_ms", {}).items()))
print("\npipeline statistics of one frame (measure on)")
for s in ["none", "both", "none-zfail", "both-zfail"]:
    f = load(s + "-fill")
    if f: print("%-11s" % s, json.dumps(f["shadow_stats"].get("pipeline")))
    if f: print("%-11s" % "", {k: f["shadow_stats"][k] for k in ["silhouette_edges", "fan_triangles", "depth_pass_triangles", "volume_triangles", "stencil_fragments"]})
PY
