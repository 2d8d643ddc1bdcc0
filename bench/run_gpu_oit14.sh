#!/usr/bin/env bash
# Issue 14 (OIT cost targets), one device call per mode, carry .gpu.
# Here:
#   cmake --build --preset release --target veil-bench            (this branch)
#   <main checkout>: cmake --build --preset release --target veil-bench   (before)
#   mkdir -p /tmp/vb && cp <main>/build/release/bench/veil-bench /tmp/vb/veil-bench-before &&
#   rm -rf /tmp/vb/shaders-before && cp -r <main>/shaders /tmp/vb/shaders-before
#   <workplace shared>/tools/gpu-bundle build/release/bench/veil-bench /tmp/vb/veil-bench-before \
#       /tmp/vb/shaders-before
#   (From a worktree: gpu-bundle needs .git to be a folder, and the device copies the
#   session's main checkout; on 2026-12-01 the bundle, shaders/ and this script were copied
#   into an ignored folder of the main checkout, carried, and run from there with a
#   `datasets` link to the checkout's.)
# There:
#   bash bench/run_gpu_oit14.sh check   image error of the moment storages against `reference`
#                                       (the fragment-interlock paths run only there)
#   bash bench/run_gpu_oit14.sh all     both, with fewer variants (one short call)
#   bash bench/run_gpu_oit14.sh bench   before/after: oit-bench-1m transparent+resolve per
#                                       technique (ratio to blend), fog.json whole frame per
#                                       technique, 1920x1080, after .20 s of GPU warm-up
set -uo pipefail
source .gpu/env.sh
R=$OUT
MODE=${1:-bench}
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv > "$R/gpu.txt"
run() { # build scene oit tag W H frames warmup [extra...]
  local build=$1 scene=$2 oit=$3 tag=$4 w=$5 h=$6 frames=$7 warm=$8; shift 8
  local exe=veil-bench shaders=$PWD/shaders
  [ "$build" = before ] && exe=veil-bench-before shaders=$GPU_FILES/shaders-before
  VEIL_SHADER_DIR=$shaders timeout 90 $exe datasets/scenes/$scene.json --oit $oit --width $w \
    --height $h --frames $frames --warmup $warm "$@" --json "$R/$tag.json" > /dev/null \
    2>> "$R/log.txt" || echo "failed: $build $scene $oit" >> "$R/log.txt"
}
# "all": the check (fewer variants) then the benchmark (fewer techniques), for one short call.
CHECK_SETS="moment-p4 moment-p6 moment-p8 moment-t3 moment-t4 moment-p4-16 moment-p6-16 \
  moment-p8-16 moment-t3-16 moment-t4-16 moment-p4-half moment-p6-half moment-p8-half \
  moment-t3-half moment-t4-half"
CHECK_SCENES="oit-bench-1m room fog"
if [ "$MODE" = all ]; then
  CHECK_SETS="moment-p6 moment-p8 moment-p6-16 moment-p8-16 moment-p6-half moment-p8-half"
  CHECK_SCENES="room oit-bench-1m"
fi
if [ "$MODE" = check ] || [ "$MODE" = all ]; then
  for scene in $CHECK_SCENES; do
    for t in $CHECK_SETS; do
      run after $scene $t "check.$scene.$t" 640 360 2 1 --error-vs reference
    done
  done
  python3 - "$R" <<'PY'
import json, glob, os, sys
R = sys.argv[1]
print(open(os.path.join(R, "gpu.txt")).read().strip())
rows = {}
for f in glob.glob(os.path.join(R, "check.*.json")):
    _, scene, t = os.path.basename(f)[:-5].split(".")
    rows[(scene, t)] = json.load(open(f))["error_vs"]
print(f"{'scene':14s} {'technique':16s} {'rmse vs reference':>18s} {'max':>8s} {'non-finite':>10s} {'vs float32':>10s}")
for (scene, t), e in sorted(rows.items()):
    base = t.replace("-16", "").replace("-half", "")
    b = rows.get((scene, base))
    ratio = e["rmse"] / b["rmse"] if b and b["rmse"] > 0 else float("nan")
    print(f"{scene:14s} {t:16s} {e['rmse']:18.5f} {e['max']:8.3f} {e['non_finite']:10d} {ratio:10.2f}")
PY
  tail -5 "$R/log.txt" 2>/dev/null
  [ "$MODE" = check ] && exit 0
fi
# Clocks ramp up during the first seconds of a call: .20 s of throwaway frames first.
end=$((SECONDS + 20))
while [ $SECONDS -lt $end ]; do
  VEIL_SHADER_DIR=$PWD/shaders veil-bench datasets/scenes/room.json --width 1920 --height 1080 \
    --frames 300 --warmup 0 > /dev/null 2>&1
done
AFTER_ONLY="moment-p6-16 moment-p8-16 moment-p4-half moment-p6-half moment-p8-half moment-t3-half"
OIT_LIST="blend wboit phenomenological-nodiff phenomenological moment-p4 moment-p6 moment-p8 \
  moment-t3 moment-p4-16 moment-t3-16 stochastic-depth reference $AFTER_ONLY"
FOG_LIST="blend wboit phenomenological moment-p6 moment-p6-16 moment-t3 stochastic-depth reference \
  moment-p6-half"
OF="30 8"; FF="40 10" # frames, warm-up frames
if [ "$MODE" = all ]; then
  OF="20 5"; FF="30 8"
  OIT_LIST="blend phenomenological-nodiff moment-p6 moment-p6-16 stochastic-depth moment-p6-half"
  FOG_LIST="blend wboit phenomenological moment-p6 moment-p6-16 stochastic-depth reference moment-p6-half"
fi
for t in $OIT_LIST; do
  case " $AFTER_ONLY " in *" $t "*) ;; *) run before oit-bench-1m $t "oit.$t.before" 1920 1080 $OF ;; esac
  run after oit-bench-1m $t "oit.$t.after" 1920 1080 $OF
done
for t in $FOG_LIST; do
  [ $t = moment-p6-half ] || run before fog $t "fog.$t.before" 1920 1080 $FF
  run after fog $t "fog.$t.after" 1920 1080 $FF
done
# The fog's share of the transparent pass: the same scene without its volumes (difference).
python3 -c "import json; d = json.load(open('datasets/scenes/fog.json')); d.pop('volumes', None); json.dump(d, open('datasets/scenes/nofog-tmp.json', 'w'))"
for t in blend moment-p6 moment-p6-16 moment-p6-half; do
  [ $t = moment-p6-half ] || run before nofog-tmp $t "nofog.$t.before" 1920 1080 $FF
  run after nofog-tmp $t "nofog.$t.after" 1920 1080 $FF
done
rm -f datasets/scenes/nofog-tmp.json
python3 - "$R" <<'PY'
import json, glob, os, sys
R = sys.argv[1]
print(open(os.path.join(R, "gpu.txt")).read().strip())
d = {}
for f in glob.glob(os.path.join(R, "*.*.*.json")):
    kind, t, build = os.path.basename(f)[:-5].split(".")
    j = json.load(open(f))
    p = {x["name"]: x["median_ms"] for x in j["passes"]}
    d[(kind, t, build)] = (p, j["total_median_ms"])
def tr(kind, t, build):
    v = d.get((kind, t, build))
    return v[0].get("transparent", 0) + v[0].get("resolve", 0) if v else float("nan")
print("\noit-bench-1m, 1920x1080, transparent + resolve (ms) and ratio to blend of the same build")
print(f"{'technique':24s} {'before ms':>10s} {'ratio':>6s} {'after ms':>10s} {'ratio':>6s}")
ts = sorted({t for (k, t, b) in d if k == "oit"}, key=lambda t: (t != "blend", t))
for t in ts:
    b, a = tr("oit", t, "before"), tr("oit", t, "after")
    bb, ab = tr("oit", "blend", "before"), tr("oit", "blend", "after")
    print(f"{t:24s} {b:10.3f} {b / bb:6.2f} {a:10.3f} {a / ab:6.2f}")
print("\nfog.json, 1920x1080, whole frame (ms, sum of pass medians) and transparent pass (ms)")
print(f"{'technique':18s} {'before frame':>12s} {'transp':>8s} {'after frame':>12s} {'transp':>8s} {'fog':>7s}")
for t in sorted({t for (k, t, b) in d if k == "fog"}, key=lambda t: (t != "blend", t)):
    b, a = d.get(("fog", t, "before")), d.get(("fog", t, "after"))
    fb = b[1] if b else float("nan"); tb = b[0].get("transparent", float("nan")) if b else float("nan")
    fa = a[1] if a else float("nan"); ta = a[0].get("transparent", float("nan")) if a else float("nan")
    fg = a[0].get("fog", float("nan")) if a else float("nan")
    print(f"{t:18s} {fb:12.3f} {tb:8.3f} {fa:12.3f} {ta:8.3f} {fg:7.3f}")
print("\nfog's share of the transparent pass = transparent(fog.json) - transparent(fog.json without volumes)")
for t in sorted({t for (k, t, b) in d if k == "nofog"}):
    for build in ("before", "after"):
        f, n = d.get(("fog", t, build)), d.get(("nofog", t, build))
        if f and n:
            print(f"{t:18s} {build:6s} {f[0]['transparent'] - n[0]['transparent']:8.3f} ms")
PY
tail -5 "$R/log.txt" 2>/dev/null
