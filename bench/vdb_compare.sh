#!/usr/bin/env bash
# vdb_render (libopenvdb-tools) against Veil's fog pass on the same lit view of the same
# volume: smoke.vdb, orthographic, 256x256, one directional light, both
# shadowing every sample (vdb_render: shadow ray per sample, 3-voxel steps; Veil: light
# transmittance volume recomputed every frame, --relight). Prints a table and the ratio
# veil fog pass / vdb_render ray-tracing time.
#
#   here (llvmpipe):  bash bench/vdb_compare.sh [CPUS]           (default: nproc)
#   GPU machine:      bash bench/vdb_compare.sh 16   (with .gpu/env.sh sourced: veil-bench
#                     and vdb_render bundled by `bench/gpu-bundle.sh build/release
#                     $(command -v vdb_render)`, bench/README.md)
# Environment: VEIL_BENCH (default build/release/bench/veil-bench), VDB_RENDER (default
# vdb_render on PATH), REPS (vdb_render runs, median; default 3), FRAMES (veil timed frames,
# default 3), OUTDIR (JSON and images; default a temp dir).
set -euo pipefail
cpus=${1:-$(nproc)}
root=$(cd "$(dirname "$0")/.." && pwd)
scene=$root/bench/scenes/smoke-ortho256.json
vdb=$root/datasets/third_party/vdb-smoke/smoke.vdb
bench=${VEIL_BENCH:-$root/build/release/bench/veil-bench}
vdbr=${VDB_RENDER:-$(command -v vdb_render || true)}
reps=${REPS:-3}
frames=${FRAMES:-3}
out=${OUTDIR:-$(mktemp -d)}
mkdir -p "$out"
if [ -z "$vdbr" ]; then
  echo "vdb_compare: vdb_render not found; installing libopenvdb-tools (scripts/install-deps.sh)"
  bash "$root/scripts/install-deps.sh"
  vdbr=$(command -v vdb_render)
fi
[ -x "$bench" ] || { echo "vdb_compare: $bench not built (cmake --build --preset release --target veil-bench)" >&2; exit 1; }
export VEIL_SHADER_DIR=${VEIL_SHADER_DIR:-$root/shaders}
export LP_NUM_THREADS=$cpus # llvmpipe's rasterizer/compute threads (ignored by other drivers)

# The same camera as the scene: ortho, 110 world units high, at (-7.4, 40.4, 200) looking -z;
# light toward (0.3, 0.3, 0) (the scene's light travels along -0.3, -0.3, 0). Steps: 1 voxel
# along the view ray (Veil: 128 steps over the ~112-voxel depth of the grid's box).
vdb_times=()
for i in $(seq "$reps"); do
  # wall: vdb_render's own "ray-tracing density ...completed in X sec"; cpu: user + sys of
  # the whole process (getrusage; includes reading the 7 MB file, ~0.04 s of one core)
  python3 -c 'import resource, subprocess, sys
subprocess.run(sys.argv[2:], stdout=open(sys.argv[1], "w"), stderr=subprocess.STDOUT, check=True)
r = resource.getrusage(resource.RUSAGE_CHILDREN)
print("cpu", r.ru_utime, r.ru_stime)' "$out/vdb.log" "$vdbr" "$vdb" "$out/vdb_render.ppm" \
    -camera ortho -frame 110 -res 256x256 -translate -7.4,40.4,200 -lookat -7.4,40.4,0 \
    -light 0.3,0.3,0 -step 1 -shadowstep 3 -cpus "$cpus" -v > "$out/time.txt"
  wall=$(grep -A1 "ray-tracing" "$out/vdb.log" | sed -n 's/.*completed in \([0-9.e+-]*\) sec.*/\1/p')
  cpu=$(awk '/^cpu/ {print $2 + $3}' "$out/time.txt")
  vdb_times+=("$wall:$cpu")
done

run_veil() { # name, extra args
  local name=$1
  shift
  "$bench" "${scene}" --width 256 --height 256 --warmup 1 --frames "$frames" "$@" \
    --json "$out/veil-$name.json" > /dev/null
}
run_veil lit --relight
run_veil lit-cached
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); d["lights"]=[]; d["volumes"][0]["path"]=sys.argv[3]; json.dump(d,open(sys.argv[2],"w"))' \
  "$scene" "$out/unlit.json" "$vdb"
scene=$out/unlit.json run_veil unlit

python3 - "$out" "$cpus" "${vdb_times[@]}" <<'PY'
import json, sys, statistics, os
out, cpus = sys.argv[1], sys.argv[2]
runs = [tuple(float(x) for x in t.split(":")) for t in sys.argv[3:]]
vdb_wall = statistics.median(r[0] for r in runs) * 1e3
vdb_cpu = statistics.median(r[1] for r in runs) * 1e3
print(f"vdb_render: {len(runs)} runs, {cpus} threads, median wall {vdb_wall:.0f} ms, "
      f"median process CPU {vdb_cpu:.0f} ms")
rows = []
for name, what in [("lit", "lit, light volume every frame"),
                   ("lit-cached", "lit, light volume cached"), ("unlit", "no light")]:
    d = json.load(open(os.path.join(out, f"veil-{name}.json")))
    p = {x["name"]: x for x in d["passes"]}["fog"]
    rows.append((what, p["median_ms"], p.get("cpu_median_ms"), d["renderer"], d["timer"]))
print(f"veil: {rows[0][3]}, timer {rows[0][4]}, LP_NUM_THREADS={cpus}")
print("| case | veil fog ms (wall) | vdb_render ms (wall) | ratio (wall) | veil fog CPU ms | vdb_render CPU ms | ratio (CPU) |")
print("|---|---:|---:|---:|---:|---:|---:|")
result = {"cpus": int(cpus), "vdb_render": {"wall_ms": vdb_wall, "cpu_ms": vdb_cpu, "runs": runs}}
for what, ms, cpu, _, _ in rows:
    c = f"{cpu:.0f} | {vdb_cpu:.0f} | {cpu / vdb_cpu:.3g}" if cpu is not None else "- | - | -"
    print(f"| {what} | {ms:.1f} | {vdb_wall:.0f} | {ms / vdb_wall:.3g} | {c} |")
    result[what] = {"wall_ms": ms, "cpu_ms": cpu}
json.dump(result, open(os.path.join(out, "vdb_compare.json"), "w"), indent=2)
PY
echo "vdb_compare: outputs in $out"
