#!/usr/bin/env bash
# Compiler launcher that records what each compile costs: CMAKE_CXX_COMPILER_LAUNCHER=
# scripts/compile-time.sh appends "user_s sys_s wall_s output" per compiler call to
# $VEIL_COMPILE_TIME_LOG (default /tmp/veil-compile-time.log). CPU seconds stay meaningful on
# a loaded machine where wall times do not (docs/ci.md).
log=${VEIL_COMPILE_TIME_LOG:-/tmp/veil-compile-time.log}
if [[ ! -x /usr/bin/time ]]; then
  echo "compile-time.sh: needs /usr/bin/time (Debian package 'time')" >&2
  exit 2
fi
out=?
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
  if [[ ${args[i]} == -o ]]; then out=${args[i + 1]}; fi
done
exec /usr/bin/time -a -o "$log" -f "%U %S %e $out" "$@"
