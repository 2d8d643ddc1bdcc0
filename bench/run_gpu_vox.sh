#!/usr/bin/env bash
# Voxelization benchmark and GPU correctness check (device run, carry .gpu): see run_gpu.sh.
set -uo pipefail
source .gpu/env.sh
export VEIL_SHADER_DIR=$PWD/shaders
{
  timeout 200 veil-voxbench bench/scenes/vox-1m.json --res 128 --runs 3 --warmup 1 --check \
    --no-openvdb --json "$OUT/vox-1m-check.json"
  timeout 200 veil-voxbench datasets/scenes/oit-bench-1m.json --res 128 --runs 3 --warmup 1 \
    --check --no-openvdb --json "$OUT/vox-oit1m-check.json"
  timeout 300 veil-voxbench bench/scenes/vox-1m.json --res 512 --slices 128 --slices 512 \
    --slices 1024 --runs 10 --warmup 2 --json "$OUT/vox-1m.json"
} 2>&1 | tee "$OUT/vox.txt"
