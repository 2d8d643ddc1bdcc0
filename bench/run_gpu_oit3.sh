#!/usr/bin/env bash
# Issue 14 item 3 (bytes per fragment: phenomenological, stochastic-depth), one device call.
# Here (worktree oit-bytes):
#   cmake --build --preset release --target veil-bench
#   mkdir -p /tmp/oit3/vb && cp <main at 1f84ddc>/build/release/bench/veil-bench \
#     /tmp/oit3/vb/veil-bench-before && cp -r <main>/shaders /tmp/oit3/vb/shaders-before
#   cd <main checkout> && <workplace shared>/tools/gpu-bundle <wt>/build/release/bench/veil-bench \
#     /tmp/oit3/vb/veil-bench-before <wt>/shaders /tmp/oit3/vb/shaders-before \
#     <wt>/bench/run_gpu_oit3.sh && mv .gpu .gpu-oit3
# There (carry .gpu-oit3): mv .gpu-oit3 .gpu && source .gpu/env.sh && bash $GPU_FILES/run_gpu_oit3.sh
# datasets/scenes/oit-bench-1m.json (1.12M transparent triangles), 1920x1080, 5 warm-up + 30
# timed frames per case, two repetitions (a, b) interleaved; cost = transparent + resolve
# (GL_TIME_ELAPSED medians), ratio to `blend` of the same build in the same call.
# Cases: "before" = veil-bench + shaders of main (1f84ddc), "after" = this branch; the
# properties change the technique's bytes per fragment and its fragment work separately:
#   phen-nodiff          after 20 B (A RGBA16F, beta RGBA16, delta RG16F); before 24 B
#   phen-nodiff-norefr   refraction off: after 16 B (no delta target); before 24 B (RT2 written 0)
#   sd-S                 stochastic-depth at S = 1, 2, 4, 8 samples (3 geometry passes each)
#   stoch-8              basic stochastic, 1 geometry pass at 8x MSAA
set -uo pipefail
[ -n "${GPU_FILES:-}" ] || source .gpu/env.sh
R=${OUT:-/tmp/oit3-out}; mkdir -p "$R"
W=${W:-1920}; H=${H:-1080}; FR=${FR:-30}; WU=${WU:-5}; WARM_S=${WARM_S:-20}
SCENE=${SCENE:-datasets/scenes/oit-bench-1m.json}
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv > "$R/gpu.txt" 2>/dev/null ||
  echo "no nvidia-smi" > "$R/gpu.txt"
case_oit() { # tag -> render.oit JSON
  case $1 in
    blend) echo '{"type":"blend"}' ;;
    wboit) echo '{"type":"wboit"}' ;;
    phen) echo '{"type":"phenomenological"}' ;;
    phen-nodiff) echo '{"type":"phenomenological-nodiff"}' ;;
    phen-nodiff-norefr) echo '{"type":"phenomenological-nodiff","refraction":false}' ;;
    sd-*) echo "{\"type\":\"stochastic-depth\",\"samples\":${1#sd-}}" ;;
    stoch-8) echo '{"type":"stochastic","samples":8}' ;;
  esac
}
run() { # build tag rep
  local exe=veil-bench sh=$GPU_FILES/shaders
  [ "$1" = before ] && exe=veil-bench-before sh=$GPU_FILES/shaders-before
  VEIL_SHADER_DIR=$sh timeout 60 $exe $SCENE --set "render.oit=$(case_oit $2)" --width $W \
    --height $H --frames $FR --warmup $WU --json "$R/$1.$2.$3.json" > /dev/null 2>> "$R/log.txt" ||
    echo "failed: $1 $2 $3" >> "$R/log.txt"
}
# Clocks ramp up during the first seconds of a call: throwaway frames first.
end=$((SECONDS + WARM_S))
while [ $SECONDS -lt $end ]; do
  VEIL_SHADER_DIR=$GPU_FILES/shaders veil-bench datasets/scenes/room.json --width $W --height $H \
    --frames 300 --warmup 0 > /dev/null 2>&1
done
AFTER="blend wboit phen-nodiff phen phen-nodiff-norefr sd-8 sd-4 sd-2 sd-1 stoch-8"
BEFORE="blend phen-nodiff phen phen-nodiff-norefr sd-8"
for rep in a b; do
  for t in $AFTER; do
    run after $t $rep
    case " $BEFORE " in *" $t "*) run before $t $rep ;; esac
  done
done
# Image error against `reference` (640x360, 2 frames), before and after.
for b in before after; do
  exe=veil-bench sh=$GPU_FILES/shaders
  [ $b = before ] && exe=veil-bench-before sh=$GPU_FILES/shaders-before
  for t in phenomenological phenomenological-nodiff stochastic-depth; do
    VEIL_SHADER_DIR=$sh timeout 60 $exe $SCENE --oit $t --width 640 --height 360 --frames 2 \
      --warmup 1 --error-vs reference --json "$R/err.$b.$t.json" > /dev/null 2>> "$R/log.txt" ||
      echo "failed: err $b $t" >> "$R/log.txt"
  done
done
python3 - "$R" <<'PY'
import json, glob, os, sys, statistics
R = sys.argv[1]
print(open(os.path.join(R, "gpu.txt")).read().strip())
d = {}
for f in glob.glob(os.path.join(R, "*.*.[ab].json")):
    b, t, rep = os.path.basename(f)[:-5].split(".")
    j = json.load(open(f))
    p = {x["name"]: x["median_ms"] for x in j["passes"]}
    d[(b, t, rep)] = (p.get("transparent", 0) + p.get("resolve", 0), p.get("transparent", 0),
                      p.get("resolve", 0), j.get("oit_stats", {}))
print("\noit-bench-1m, 1920x1080, transparent + resolve (ms), ratio to blend of the same build and rep")
print(f"{'case':20s} {'build':6s} {'rep':3s} {'transp':>8s} {'resolve':>8s} {'sum':>8s} {'ratio':>6s}  stats")
for (b, t, rep) in sorted(d, key=lambda k: (k[1], k[0], k[2])):
    s, tr, rs, st = d[(b, t, rep)]
    base = d.get((b, "blend", rep))
    ratio = s / base[0] if base and base[0] > 0 else float("nan")
    print(f"{t:20s} {b:6s} {rep:3s} {tr:8.3f} {rs:8.3f} {s:8.3f} {ratio:6.3f}  {json.dumps(st) if st else ''}")
print("\nimage error vs reference, oit-bench-1m 640x360")
for f in sorted(glob.glob(os.path.join(R, "err.*.json"))):
    e = json.load(open(f))["error_vs"]
    print(f"{os.path.basename(f)[4:-5]:40s} rmse {e['rmse']:.6f} max {e['max']:.4f} non-finite {e.get('non_finite', 0)}")
PY
tail -5 "$R/log.txt" 2>/dev/null
