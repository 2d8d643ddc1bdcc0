#!/usr/bin/env bash
# Runs every benchmark of bench/RESULTS.md on the GPU machine in one device call.
# Here:  cmake --build build --target veil-bench veil-voxbench
#        <workplace shared>/tools/gpu-bundle build/bench/veil-bench build/bench/veil-voxbench
#        (the bundling tool of the workplace, run here; no data is read from outside the repo)
#        (datasets/third_party travels with the working tree)
# There (device run, carry .gpu):  bash bench/run_gpu.sh   -> $OUT/bench-all.json + logs
set -uo pipefail
source .gpu/env.sh
export VEIL_SHADER_DIR=$PWD/shaders
R=$(mktemp -d)
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv > "$R/gpu.txt"
W=1920; H=1080
for t in blend wboit phenomenological-nodiff phenomenological moment-p6 moment-p4 moment-p8 \
         moment-t3 moment-t4 moment-p4-16 moment-t3-16 stochastic stochastic-alpha \
         stochastic-depth reference; do
  timeout 120 veil-bench datasets/scenes/oit-bench-1m.json --oit $t --width $W --height $H \
    --frames 40 --warmup 8 --json "$R/oit-$t.json" > /dev/null 2>> "$R/log.txt" ||
    echo "oit $t failed" >> "$R/log.txt"
done
for r in 1 2 4; do
  extra=""; [ $r = 1 ] && extra="--cpu-fog 128 72"
  timeout 200 veil-bench bench/scenes/cloud256.json --set render.fog_resolution=$r --width $W \
    --height $H --frames 30 --warmup 5 $extra --json "$R/fog-cloud256-r$r.json" > /dev/null \
    2>> "$R/log.txt" || echo "fog cloud r$r failed" >> "$R/log.txt"
  timeout 120 veil-bench datasets/scenes/fog.json --set render.fog_resolution=$r --set render.fog_steps=128 \
    --width $W --height $H --frames 30 --warmup 5 --json "$R/fog-smoke-r$r.json" > /dev/null \
    2>> "$R/log.txt" || echo "fog smoke r$r failed" >> "$R/log.txt"
done
timeout 240 veil-voxbench datasets/scenes/oit-bench-1m.json --res 512 --slices 128 --slices 512 \
  --slices 1024 --runs 10 --warmup 2 --json "$R/vox-1m.json" > "$R/vox.txt" 2>> "$R/log.txt" ||
  echo "voxbench failed" >> "$R/log.txt"
timeout 200 veil-voxbench datasets/scenes/oit-bench-1m.json --res 128 --runs 3 --warmup 1 --check \
  --no-openvdb --json "$R/vox-check.json" >> "$R/vox.txt" 2>> "$R/log.txt" ||
  echo "voxbench check failed" >> "$R/log.txt"
python3 - "$R" "$OUT/bench-all.json" <<'PY'
import json, os, sys
src, dst = sys.argv[1], sys.argv[2]
out = {"gpu": open(os.path.join(src, "gpu.txt")).read()}
for f in sorted(os.listdir(src)):
    if f.endswith(".json"):
        try: out[f[:-5]] = json.load(open(os.path.join(src, f)))
        except Exception as e: out[f[:-5]] = str(e)
json.dump(out, open(dst, "w"), indent=1)
PY
cp "$R/log.txt" "$R/vox.txt" "$OUT/" 2>/dev/null
python3 - "$OUT/bench-all.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(d["gpu"])
base = None
for k, v in d.items():
    if k.startswith("oit-") and isinstance(v, dict):
        tr = sum(p["median_ms"] for p in v["passes"] if p["name"] in ("transparent", "resolve"))
        if k == "oit-blend": base = tr
        print(f"{k:28s} transparent+resolve {tr:8.3f} ms  ratio {tr/base if base else 0:6.2f}")
    if k.startswith("fog-") and isinstance(v, dict):
        f = [p["median_ms"] for p in v["passes"] if p["name"] == "fog"]
        print(f"{k:28s} fog {f[0] if f else -1:8.3f} ms  {v.get('cpu_fog', '')}")
PY
tail -5 "$OUT/log.txt" 2>/dev/null; cat "$OUT/vox.txt" 2>/dev/null | tail -25
