#!/usr/bin/env bash
# Issue 14 OIT cost (branch oit-cost), one device call: moment-p6-half with b_0 in RGBA16F
# (b0_half) against b_0 in RGBA32F, and phenomenological(-nodiff) with and without refraction.
# Here (worktree oit-cost): cmake --build --preset release --target veil-bench;
#   mkdir -p /tmp/oitcost/vb && cp /work/main/build/release/bench/veil-bench \
#     /tmp/oitcost/vb/veil-bench-before && cp -r /work/main/shaders /tmp/oitcost/vb/shaders-before
#   cd /work/main && <shared>/tools/gpu-bundle <wt>/build/release/bench/veil-bench \
#     /tmp/oitcost/vb/veil-bench-before <wt>/shaders /tmp/oitcost/vb/shaders-before \
#     <wt>/bench/run_gpu_oitcost.sh && mv .gpu .gpu-oitcost
# There (carry .gpu-oitcost): mv .gpu-oitcost .gpu && source .gpu/env.sh && bash $GPU_FILES/run_gpu_oitcost.sh
# datasets/scenes/oit-bench-1m.json, 1920x1080, WU warm-up + FR timed frames per case, two
# repetitions (a, b) interleaved before/after; cost = transparent + resolve medians, ratio to
# `blend` of the same build and repetition.
set -uo pipefail
[ -n "${GPU_FILES:-}" ] || source .gpu/env.sh
R=${OUT:-/tmp/oitcost-out}; mkdir -p "$R"
W=${W:-1920}; H=${H:-1080}; FR=${FR:-30}; WU=${WU:-5}; WARM_S=${WARM_S:-20}
EW=${EW:-640}; EH=${EH:-360}
SCENE=${SCENE:-datasets/scenes/oit-bench-1m.json}
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv > "$R/gpu.txt" 2>/dev/null ||
  echo "no nvidia-smi" > "$R/gpu.txt"
BIAS16=6e-4 # p6 16-bit bias (MOMENTS-NOTES.md), the default of moment-p6-half
case_oit() { # tag -> render.oit JSON
  case $1 in
    blend) echo '{"type":"blend"}' ;;
    p6) echo '{"type":"moment-p6"}' ;;
    p6-16) echo '{"type":"moment-p6-16"}' ;;
    p6-half) echo '{"type":"moment-p6-half"}' ;;
    p6-half-b0) echo '{"type":"moment-p6-half","b0_half":true}' ;;
    p6-half-b032) echo '{"type":"moment-p6-half","b0_half":false}' ;;
    p6-half-b0-x3) echo "{\"type\":\"moment-p6-half\",\"b0_half\":true,\"bias\":$(python3 -c "print($BIAS16*3)")}" ;;
    p6-half-b0-x10) echo "{\"type\":\"moment-p6-half\",\"b0_half\":true,\"bias\":$(python3 -c "print($BIAS16*10)")}" ;;
    phen-nodiff) echo '{"type":"phenomenological-nodiff"}' ;;
    phen-nodiff-norefr) echo '{"type":"phenomenological-nodiff","refraction":false}' ;;
    reference) echo '{"type":"reference"}' ;;
  esac
}
bin() { # build -> "exe shaders"
  if [ "$1" = before ]; then echo "veil-bench-before $GPU_FILES/shaders-before"
  else echo "veil-bench $GPU_FILES/shaders"; fi
}
run() { # build tag rep
  set -- "$1" "$2" "$3" $(bin "$1")
  VEIL_SHADER_DIR=$5 timeout 60 $4 $SCENE --set "render.oit=$(case_oit $2)" --width $W \
    --height $H --frames $FR --warmup $WU --json "$R/$1.$2.$3.json" > /dev/null 2>> "$R/log.txt" ||
    echo "failed: $1 $2 $3" >> "$R/log.txt"
}
err() { # build tag
  set -- "$1" "$2" $(bin "$1")
  VEIL_SHADER_DIR=$4 timeout 60 $3 $SCENE --set "render.oit=$(case_oit $2)" --width $EW \
    --height $EH --frames 2 --warmup 1 --error-vs reference --json "$R/err.$1.$2.json" \
    > /dev/null 2>> "$R/log.txt" || echo "failed: err $1 $2" >> "$R/log.txt"
}
# Clocks ramp up during the first seconds of a call: throwaway frames first.
end=$((SECONDS + WARM_S))
while [ $SECONDS -lt $end ]; do
  VEIL_SHADER_DIR=$GPU_FILES/shaders veil-bench datasets/scenes/room.json --width $W --height $H \
    --frames 300 --warmup 0 > /dev/null 2>&1
done
AFTER="blend p6-16 p6-half p6-half-b032 p6-half-b0-x3 phen-nodiff phen-nodiff-norefr"
BEFORE="blend p6-half phen-nodiff"
for rep in a b; do
  for t in $AFTER; do
    run after $t $rep
    case " $BEFORE " in *" $t "*) run before $t $rep ;; esac
  done
done
for t in p6 p6-16 p6-half p6-half-b032 p6-half-b0-x3 p6-half-b0-x10 phen-nodiff; do err after $t; done
err before p6-half; err before phen-nodiff
python3 - "$R" <<'PY'
import json, glob, os, sys
R = sys.argv[1]
print(open(os.path.join(R, "gpu.txt")).read().strip())
d = {}
for f in glob.glob(os.path.join(R, "*.*.[ab].json")):
    b, t, rep = os.path.basename(f)[:-5].split(".")
    p = {x["name"]: x["median_ms"] for x in json.load(open(f))["passes"]}
    d[(b, t, rep)] = p.get("transparent", 0) + p.get("resolve", 0)
print("\noit-bench-1m transparent + resolve ms (ratio to blend, same build and rep)")
print("| build | case | a ms | a ratio | b ms | b ratio |")
for b in ("before", "after"):
    for t in sorted({k[1] for k in d if k[0] == b}):
        row = [b, t]
        for rep in "ab":
            ms, bl = d.get((b, t, rep)), d.get((b, "blend", rep))
            row += ["%.3f" % ms if ms else "-", "%.2f" % (ms / bl) if ms and bl else "-"]
        print("| " + " | ".join(row) + " |")
print("\nimage error vs reference")
for f in sorted(glob.glob(os.path.join(R, "err.*.json"))):
    j = json.load(open(f))
    e = {k: v for k, v in j.items() if "err" in k or "rmse" in k}
    print(os.path.basename(f), json.dumps(e)[:300])
PY
ls "$R" | wc -l
# Keep at most 8 files coming back: the table is on stdout.
mkdir -p "$R/keep"; cp "$R"/log.txt "$R"/gpu.txt "$R"/err.after.p6-half.json "$R"/after.p6-half.a.json "$R"/err.after.p6.json "$R/keep/" 2>/dev/null
find "$R" -maxdepth 1 -type f ! -name log.txt ! -name gpu.txt -delete; mv "$R"/keep/* "$R"/ ; rmdir "$R/keep"
