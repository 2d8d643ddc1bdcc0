#!/usr/bin/env bash
# Issue 14's table (run_gpu_issue14_table.sh) for two builds in one device call, alternating
# A B A B so that clock drift shows as a/b spread: A = a baseline build bundled as
# $GPU_FILES/base.tgz (veil-bench-base and its shaders-base/), B = the bundled veil-bench with
# this tree's shaders. Here:
#   tools/gpu-bundle build/release/bench/veil-bench base.tgz bench/run_gpu_ab.sh
# there: bash $GPU_FILES/run_gpu_ab.sh  -> the four tables on stdout.
set -uo pipefail
[ -n "${GPU_FILES:-}" ] || source .gpu/env.sh
tree=$PWD
base=$(mktemp -d)
tar xzf "$GPU_FILES/base.tgz" -C "$base"
mkdir -p "$base/bin" && ln -sf "$base/veil-bench-base" "$base/bin/veil-bench"
for rep in a b; do
  for build in base main; do
    echo "=== $build ($rep)"
    out=$(mktemp -d)
    if [ $build = base ]; then
      (cd "$tree" && PATH="$base/bin:$PATH" VEIL_SHADER_DIR="$base/shaders-base" OUT=$out \
        bash bench/run_gpu_issue14_table.sh)
    else
      (cd "$tree" && VEIL_SHADER_DIR="$tree/shaders" OUT=$out bash bench/run_gpu_issue14_table.sh)
    fi
  done
done
