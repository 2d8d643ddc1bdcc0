#!/usr/bin/env bash
# Builds the fuzz preset and runs each libFuzzer target of tests/fuzz for SECONDS (default
# 60) over a copy of its seed corpus; exits non-zero on any finding and prints the input that
# caused it (docs/fuzzing.md). The repository's corpora are never written to.
#
#   scripts/fuzz.sh [SECONDS]
#   FUZZ_TOTAL_SECONDS=S        instead of SECONDS per target, S shared equally by the targets
#                               (CI: 120 s for seven targets, 17 s each)
#   FUZZ_TARGETS="scene mesh"   the targets to run (default: scene volume mesh suite results
#                               time frames)
#   FUZZ_JOBS=N                 N fuzzing processes per target (libFuzzer -fork=N)
#   FUZZ_SEED=S                 libFuzzer's -seed (default 1, so CI runs repeat)
#   FUZZ_REPLAY_ONLY="volume"   targets that only replay their seeds and regressions once
#                               (-runs=0), no mutation: for a target whose open findings
#                               (tests/fuzz/findings/) would otherwise fail the run
#   FUZZ_BUILD_JOBS=N           build parallelism (default: nproc)
#   FUZZ_PRESET=P               the CMake preset whose build holds the targets (default fuzz, -O2;
#                               CI: asan-ubsan, whose -O1 sanitizer build of the libraries the
#                               unit tests already made is reused: it builds the fuzz targets too)
#   FUZZ_TIMEOUT=S              libFuzzer's per-input -timeout (default 10; 60 for volume, below)
#   FUZZ_PARALLEL=1             run the targets at the same time instead of one after another
#                               (CI: three targets on two cores for 1.5 x SECONDS each get
#                               about the CPU time of SECONDS each, in half the wall time)
set -euo pipefail
cd "$(dirname "$0")/.."

targets=${FUZZ_TARGETS:-scene volume mesh suite results time frames}
seconds=${1:-60}
if [[ -n ${FUZZ_TOTAL_SECONDS:-} ]]; then
  count=$(wc -w <<<"$targets")
  seconds=$((FUZZ_TOTAL_SECONDS / count))
  ((seconds > 0)) || { echo "fuzz: FUZZ_TOTAL_SECONDS=$FUZZ_TOTAL_SECONDS is under 1 s per target" >&2; exit 2; }
fi
jobs=${FUZZ_JOBS:-1}
seed=${FUZZ_SEED:-1}
preset=${FUZZ_PRESET:-fuzz}
build=build/$preset
artifacts=$build/artifacts
runs=$build/corpus-run

cmake --preset "$preset" >/dev/null
fuzz_targets=()
for t in $targets; do fuzz_targets+=("veil_fuzz_$t"); done
cmake --build "$build" -j "${FUZZ_BUILD_JOBS:-$(nproc)}" --target "${fuzz_targets[@]}"

# LeakSanitizer stays on (libFuzzer's -detect_leaks=1): OpenVDB's and TBB's global state is
# still reachable at exit and is not reported. UBSan findings abort (the build also passes
# -fno-sanitize-recover=undefined).
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:symbolize=1}
# Leaks inside libassimp's own error paths are not Veil's (tests/fuzz/lsan_suppressions.txt
# says why); everything else LeakSanitizer reports is still a finding.
export LSAN_OPTIONS="suppressions=$PWD/tests/fuzz/lsan_suppressions.txt${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

# Per-input time limit. The volume target's is 60 s: its trial reads (src/grid/vdb_file.cpp)
# allocate what a damaged compressed-size field in the file asks for before OpenVDB finds the
# data missing, and under ASan a 2.9 GB allocation is touched page by page: a 30 KB input took
# 18 s in the fuzz build and 0.46 s (a one-line "corrupt" error) in the release build.
declare -A timeout_of=([volume]=60)

mkdir -p "$artifacts"
for t in $targets; do
  exe=$build/tests/fuzz/veil_fuzz_$t
  test -x "$exe" || { echo "fuzz: no target '$t' ($exe)" >&2; exit 2; }
done
# Start each target (in the background with FUZZ_PARALLEL=1), then check each one's result.
declare -A pid rcs
for t in $targets; do
  exe=$build/tests/fuzz/veil_fuzz_$t
  # The run's corpus: the seeds and every saved finding (so a fixed crash stays fixed), in a
  # folder of the build where libFuzzer may add what it finds.
  rm -rf "${runs:?}/$t"
  mkdir -p "$runs/$t"
  cp tests/fuzz/corpus/"$t"/* "$runs/$t"/
  if compgen -G "tests/fuzz/regressions/$t/*" >/dev/null; then
    cp tests/fuzz/regressions/"$t"/* "$runs/$t"/
  fi
  rm -f "$artifacts/$t"-*
  log=$build/fuzz-$t.log
  mode=(-max_total_time="$seconds")
  what="for ${seconds}s"
  if [[ " ${FUZZ_REPLAY_ONLY:-} " == *" $t "* ]]; then
    mode=(-runs=0)
    what="replaying its seeds and regressions only (FUZZ_REPLAY_ONLY)"
  elif ((jobs > 1)); then
    mode+=(-fork="$jobs")
  fi
  dict=()
  if [[ -f tests/fuzz/$t.dict ]]; then dict=(-dict="tests/fuzz/$t.dict"); fi
  echo "fuzz: $t $what over $(find "$runs/$t" -type f | wc -l) inputs (log: $log)"
  limit=${FUZZ_TIMEOUT:-${timeout_of[$t]:-10}}
  # libFuzzer saves an input that runs past -report_slow_units as a "slow-unit" artifact
  # without failing; past -timeout it fails. Only the latter is a finding here, so the two
  # limits are the same.
  run=("$exe" "${mode[@]}" -timeout="$limit" -report_slow_units="$limit" -rss_limit_mb=2048 -seed="$seed" -print_final_stats=1
       "${dict[@]}" -artifact_prefix="$artifacts/$t-" "$runs/$t")
  if [[ ${FUZZ_PARALLEL:-0} == 1 ]]; then
    "${run[@]}" >"$log" 2>&1 &
    pid[$t]=$!
  else
    rcs[$t]=0
    "${run[@]}" >"$log" 2>&1 || rcs[$t]=$?
  fi
done
status=0
for t in $targets; do
  exe=$build/tests/fuzz/veil_fuzz_$t
  log=$build/fuzz-$t.log
  rc=${rcs[$t]:-0}
  if [[ -n ${pid[$t]:-} ]]; then wait "${pid[$t]}" || rc=$?; fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  echo "fuzz: $t: exit $rc, ${execs:-?} runs, ${rate:-?} exec/s, corpus $(find "$runs/$t" -type f | wc -l) inputs"
  # The inputs libFuzzer saved, as it reports them (a child process of the code under test
  # may inherit libFuzzer's handlers; fuzzer_main.cpp resets them, and only this process's
  # log counts).
  found=$(sed -n 's/.*Test unit written to //p' "$log" | grep -v -- '-slow-unit-' | sort -u || true)
  slow=$(sed -n 's/.*Test unit written to //p' "$log" | grep -- '-slow-unit-' | sort -u || true)
  for f in $slow; do
    echo "fuzz: $t: slow input (under the ${limit}s limit, not a finding): $f"
  done
  if ((rc != 0)) || [[ -n $found ]]; then
    status=1
    grep -E '^==[0-9]+==|^SUMMARY|runtime error|uncaught exception|terminate called|ALARM|out-of-memory' \
      "$log" | head -20 >&2 || true
    for f in $found; do
      echo "fuzz: $t: finding: $f (replay: $exe $f)" >&2
    done
    [[ -n $found ]] || echo "fuzz: $t: exited $rc without an artifact; see $log" >&2
  fi
done
exit $status
