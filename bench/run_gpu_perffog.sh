#!/usr/bin/env bash
# Issue 14 items 4 and 5 on the GPU machine, one device call (carry .gpu made by
#   /work/shared/tools/gpu-bundle build/release/bench/veil-bench /usr/bin/vdb_render).
#  4. bench/vdb_compare.sh on 16 cores: vdb_render vs the fog pass on smoke-ortho256.
#  5. `reference` at 1920x1080 on default.json and fog.json: fragments, pool, deepest list,
#     drops with the old fixed limit (128) and the new default; pass times.
set -uo pipefail
source .gpu/env.sh
export VEIL_SHADER_DIR=$PWD/shaders
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv,noheader
# Clocks ramp up during the first seconds of a call: a throwaway warm-up first.
timeout 60 veil-bench datasets/scenes/fog.json --width 1920 --height 1080 --frames 300 \
  --warmup 20 > /dev/null 2>&1
mkdir -p "$OUT/vdb"
VEIL_BENCH=$(command -v veil-bench) VDB_RENDER=$(command -v vdb_render) OUTDIR=$OUT/vdb \
  REPS=3 FRAMES=30 timeout 120 bash bench/vdb_compare.sh 16
rm -f "$OUT"/vdb/*.ppm "$OUT"/vdb/*.log "$OUT"/vdb/time.txt "$OUT"/vdb/unlit.json
for s in default fog; do
  for limit in 128 256 512; do
    timeout 60 veil-bench datasets/scenes/$s.json --set render.oit.type=reference \
      --set render.oit.max_fragments_per_pixel=$limit --width 1920 --height 1080 \
      --frames 20 --warmup 5 --json "$OUT/ref-$s-$limit.json" > /dev/null 2>> "$OUT/log.txt" ||
      echo "failed: ref $s $limit" >> "$OUT/log.txt"
  done
done
timeout 60 veil-bench datasets/scenes/fog.json --set render.oit.type=blend --width 1920 \
  --height 1080 --frames 20 --warmup 5 --json "$OUT/blend-fog.json" > /dev/null 2>> "$OUT/log.txt"
python3 - "$OUT/blend-fog.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); p = {x["name"]: x["median_ms"] for x in d["passes"]}
print(f"fog.json blend (baseline, same call): fog {p['fog']:.3f} transparent {p['transparent']:.3f} "
      f"resolve {p['resolve']:.3f} frame {d['total_median_ms']:.3f} ms")
PY
python3 - "$OUT" <<'PY'
import json, sys, os
print("| scene | max_fragments_per_pixel | fragments | pool nodes | deepest list | dropped | fog ms | transparent ms | resolve ms | frame ms |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for s in ["default", "fog"]:
    for limit in [128, 256, 512]:
        f = os.path.join(sys.argv[1], f"ref-{s}-{limit}.json")
        if not os.path.exists(f):
            print(f"| {s} | {limit} | failed |"); continue
        d = json.load(open(f)); st = d["oit_stats"]
        p = {x["name"]: x["median_ms"] for x in d["passes"]}
        print(f"| {s} | {limit} | {st['fragments']} | {st['pool_nodes']} | {st['max_list_length']} | "
              f"{st['pixel_overflow_fragments']} | {p.get('fog', 0):.3f} | {p['transparent']:.3f} | "
              f"{p['resolve']:.3f} | {d['total_median_ms']:.3f} |")
PY
cat "$OUT/log.txt" 2>/dev/null | tail -5
