#!/usr/bin/env bash
# `reference` transparent-pass regression on fog.json (05c7bf3 -> 4b89c45, bench/RESULTS.md
# "reference transparent pass"): veil-bench built at several commits, each with its own
# shaders, plus shader variants of one binary, interleaved, two repetitions, one device call.
# Here: copy each binary to veil-bench-<tag> and its shaders/ to shaders-<tag> (VARIANTS below:
# "binary-tag:shader-tag"), tools/gpu-bundle them with this script; there (carry .gpu):
#   bash $GPU_FILES/run_gpu_refregress.sh  -> table on stdout, JSON in $OUT.
set -uo pipefail
[ -n "${GPU_FILES:-}" ] || source .gpu/env.sh
R=$OUT
VARIANTS=${VARIANTS:-"05c7bf3:05c7bf3 f012d87:f012d87 4b89c45:4b89c45 main:main main:noregion main:fix"}
W=${W:-1920} H=${H:-1080} FRAMES=${FRAMES:-40} WARMUP=${WARMUP:-10}
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.txt" 2>/dev/null || true
end=$((SECONDS + ${WARM_S:-15}))
while [ $SECONDS -lt $end ]; do
  VEIL_SHADER_DIR=$GPU_FILES/shaders-main veil-bench-main datasets/scenes/room.json --width $W \
    --height $H --frames 300 --warmup 0 > /dev/null 2>&1
done
for rep in a b; do
  for v in $VARIANTS; do
    b=${v%%:*} s=${v##*:}
    [ -x "$(command -v veil-bench-$b)" ] && [ -d "$GPU_FILES/shaders-$s" ] || continue
    for t in ${TECHS:-reference}; do
      VEIL_SHADER_DIR=$GPU_FILES/shaders-$s timeout 90 veil-bench-$b datasets/scenes/fog.json \
        --oit $t --width $W --height $H --frames $FRAMES --warmup $WARMUP \
        --json "$R/$b.$s.$t.$rep.json" > /dev/null 2>> "$R/log.txt" || echo "failed $v $t" >> "$R/log.txt"
    done
  done
done
python3 - "$R" <<'PY'
import json, glob, os, sys
R = sys.argv[1]
try: print(open(os.path.join(R, "gpu.txt")).read().strip())
except OSError: pass
for f in sorted(glob.glob(os.path.join(R, "*.json"))):
    j = json.load(open(f)); p = {x["name"]: x["median_ms"] for x in j["passes"]}
    st = j.get("oit_stats", {})
    print(f"{os.path.basename(f)[:-5]:36s} frame {j['total_median_ms']:8.3f} fog {p.get('fog',0):7.3f} "
          f"transparent {p.get('transparent',0):7.3f} resolve {p.get('resolve',0):6.3f} {json.dumps(st)[:120]}")
PY
tail -3 "$R/log.txt" 2>/dev/null
