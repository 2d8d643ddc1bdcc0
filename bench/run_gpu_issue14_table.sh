#!/usr/bin/env bash
# Issue 14's table (used after the fourth and the fifth session's merges), one device call,
# carry .gpu. Here: tools/gpu-bundle build/release/bench/veil-bench; there:
#   bash bench/run_gpu_issue14_table.sh  -> tables on stdout, per-case JSON in $OUT (8 come back).
# oit-bench-1m: transparent + resolve per technique, ratio to blend; fog.json: whole frame (sum
# of pass medians) and the fog and transparent passes per technique; default.json and fog.json
# under `reference`: the list statistics (dropped fragments) at 1920x1080.
set -uo pipefail
[ -n "${GPU_FILES:-}" ] || source .gpu/env.sh
export VEIL_SHADER_DIR=${VEIL_SHADER_DIR:-$PWD/shaders}
R=$OUT
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv > "$R/gpu.txt"
run() { # scene oit tag frames warmup
  timeout 90 veil-bench datasets/scenes/$1.json --oit $2 --width 1920 --height 1080 \
    --frames $4 --warmup $5 --json "$R/$3.json" > /dev/null 2>> "$R/log.txt" ||
    echo "failed: $1 $2" >> "$R/log.txt"
}
# Clocks ramp up during the first seconds of a call: 20 s of throwaway frames first.
end=$((SECONDS + 20))
while [ $SECONDS -lt $end ]; do
  veil-bench datasets/scenes/room.json --width 1920 --height 1080 --frames 300 --warmup 0 \
    > /dev/null 2>&1
done
for t in blend wboit phenomenological-nodiff phenomenological moment-p6 moment-p6-16 \
  moment-p6-half stochastic-depth reference; do
  run oit-bench-1m $t "oit.$t" 30 8
done
for t in blend wboit phenomenological moment-p6 moment-p6-16 moment-p6-half stochastic-depth \
  reference; do
  run fog $t "fog.$t" 40 10
done
run default reference "default.reference" 10 3
python3 - "$R" <<'PY'
import json, glob, os, sys
R = sys.argv[1]
print(open(os.path.join(R, "gpu.txt")).read().strip())
d = {}
for f in glob.glob(os.path.join(R, "*.*.json")):
    kind, t = os.path.basename(f)[:-5].split(".", 1)
    j = json.load(open(f))
    d[(kind, t)] = ({x["name"]: x["median_ms"] for x in j["passes"]}, j["total_median_ms"],
                    j.get("oit_stats", {}))
def tr(t):
    p = d.get(("oit", t))
    return p[0].get("transparent", 0) + p[0].get("resolve", 0) if p else float("nan")
print("\noit-bench-1m, 1920x1080, transparent + resolve (ms), ratio to blend, 8 warm-up + 30 frames")
for t in sorted({t for (k, t) in d if k == "oit"}, key=lambda t: (t != "blend", t)):
    p = d[("oit", t)][0]
    print(f"{t:24s} {tr(t):9.3f} {tr(t) / tr('blend'):6.2f}   transparent {p.get('transparent', 0):8.3f}  resolve {p.get('resolve', 0):7.3f}")
print("\nfog.json, 1920x1080, whole frame (sum of pass medians), fog and transparent passes (ms)")
for t in sorted({t for (k, t) in d if k == "fog"}, key=lambda t: (t != "blend", t)):
    p, tot, _ = d[("fog", t)]
    print(f"{t:18s} frame {tot:8.3f}  fog {p.get('fog', 0):7.3f}  transparent {p.get('transparent', 0):7.3f}  " +
          "  ".join(f"{k} {v:.3f}" for k, v in p.items() if k.startswith("shadow")))
for key in (("fog", "reference"), ("default", "reference")):
    if key in d:
        s = d[key][2]
        print(f"{key[0]}.json reference 1920x1080: fragments {s.get('fragments')}, dropped "
              f"{s.get('pool_dropped_fragments')}, pixel overflow {s.get('pixel_overflow_fragments')}, "
              f"max list {s.get('max_list_length')}, pool {s.get('pool_mib')} MiB")
PY
tail -5 "$R/log.txt" 2>/dev/null
