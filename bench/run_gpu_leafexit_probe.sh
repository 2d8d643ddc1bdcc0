#!/usr/bin/env bash
# Probe (fifth session): fog.json at 1920x1080, `blend` and `reference`, with main's shaders and
# with a copy of them, shaders_noentry, where leafExit() in volume/volume_common.glsl lacks the
# branch for points outside the stored bounds. Here: copy shaders/ to shaders_noentry, delete
# that branch, then tools/gpu-bundle build/release/bench/veil-bench shaders shaders_noentry
# bench/run_gpu_leafexit_probe.sh; there: bash $GPU_FILES/run_gpu_leafexit_probe.sh.
set -uo pipefail
R=$OUT
end=$((SECONDS + 15))
while [ $SECONDS -lt $end ]; do
  veil-bench datasets/scenes/room.json --width 1920 --height 1080 --frames 300 --warmup 0 > /dev/null 2>&1
done
for rep in a b; do
  for v in main noentry; do
    if [ $v = main ]; then export VEIL_SHADER_DIR=$GPU_FILES/shaders; else export VEIL_SHADER_DIR=$GPU_FILES/shaders_noentry; fi
    for t in blend reference; do
      veil-bench datasets/scenes/fog.json --oit $t --width 1920 --height 1080 --frames 40 --warmup 10 \
        --json "$R/$v.$t.$rep.json" > /dev/null 2>> "$R/log.txt" || echo "failed $v $t" >> "$R/log.txt"
    done
  done
done
python3 - "$R" <<'PY'
import json, glob, os, sys
for f in sorted(glob.glob(os.path.join(sys.argv[1], "*.json"))):
    j = json.load(open(f)); p = {x["name"]: x["median_ms"] for x in j["passes"]}
    print(f"{os.path.basename(f):28s} frame {j['total_median_ms']:8.3f} fog {p.get('fog',0):7.3f} transparent {p.get('transparent',0):7.3f} shadow.media {p.get('shadow.media',0):6.3f}")
PY
cat "$R/log.txt" 2>/dev/null | tail -3
