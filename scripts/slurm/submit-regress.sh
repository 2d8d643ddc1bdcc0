#!/bin/bash
# Submits a veil regression suite as a Slurm job array plus its merge job (docs/cluster.md).
#   scripts/slurm/submit-regress.sh [options] SUITE OUT
# Options (anything after -- goes to both sbatch calls, e.g. -- --account=X --partition=Y):
#   --tasks N      array size = number of shards, 1..100000 (default 4)
#   --gpu          request one GPU per task (--gres=gpu:1)
#   --time T       per-task time limit (default the script's 00:30:00)
#   --mem M        per-task memory (default the script's 4G)
#   --cpus C       CPUs per task (default the script's 2)
#   --veil PATH    the veil binary (default: veil on PATH); use one path all nodes see
#   --resume       submit only the shards without a finished report in OUT (after a task was
#                  killed, preempted or timed out), then the merge again
#   --wait         wait for the merge job and return its exit status
# Prints the job ids ("array <id>", "merge <id>").
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
tasks=4 gpu=0 resume=0 wait=0 veil=veil
extra=() task_opts=()
me=submit-regress
usage() { echo "usage: $0 [--tasks N] [--gpu] [--time T] [--mem M] [--cpus C] [--veil PATH] [--resume] [--wait] SUITE OUT [-- SBATCH-OPTIONS]" >&2; exit 2; }
fail() { echo "$me: $*" >&2; exit 2; }
# value OPTION ARGS...: the option's value (the first of ARGS), or a usage error.
value() { (($# >= 2)) && [[ -n $2 ]] || fail "$1 needs a value"; echo "$2"; }
# integer NAME VALUE MIN MAX: VALUE as a plain decimal integer (at most 9 digits after leading
# zeros) in [MIN, MAX], matched as text and never evaluated as arithmetic; else a usage error.
integer() {
  [[ $2 =~ ^0*([0-9]{1,9})$ ]] && ((10#${BASH_REMATCH[1]} >= $3 && 10#${BASH_REMATCH[1]} <= $4)) ||
    fail "$1 '$2' is not an integer in $3..$4"
  echo $((10#${BASH_REMATCH[1]}))
}
pos=()
while (($#)); do
  case $1 in
    --tasks) tasks=$(value "$@"); shift 2 ;;
    --gpu) gpu=1; shift ;;
    --time) task_opts+=("--time=$(value "$@")"); shift 2 ;;
    --mem) task_opts+=("--mem=$(value "$@")"); shift 2 ;;
    --cpus) task_opts+=("--cpus-per-task=$(integer --cpus "$(value "$@")" 1 100000)"); shift 2 ;;
    --veil) veil=$(value "$@"); shift 2 ;;
    --resume) resume=1; shift ;;
    --wait) wait=1; shift ;;
    --) shift; extra=("$@"); break ;;
    -*) echo "$me: unknown option '$1'" >&2; usage ;;
    *) pos+=("$1"); shift ;;
  esac
done
((${#pos[@]} == 2)) || usage
# Slurm's own limit on an array's size (MaxArraySize) is at most 4000001; 100000 shards is far
# more than a suite has cases.
tasks=$(integer --tasks "$tasks" 1 100000)
suite=$(realpath "${pos[0]}") out=$(realpath -m "${pos[1]}")
[[ -f $suite ]] || { echo "$me: suite '$suite' does not exist" >&2; exit 1; }
[[ $veil == */* ]] && veil=$(realpath "$veil")
mkdir -p "$out/logs"
# The array indices to run: all, or with --resume those without a finished shard report.
indices=()
for ((i = 0; i < tasks; ++i)); do
  if ((resume)) && [[ -f $out/shard-$i/results.json ]]; then continue; fi
  indices+=("$i")
done
export SUITE=$suite OUT=$out VEIL=$veil VEIL_SHARDS=$tasks
gres=()
((gpu)) && gres=(--gres=gpu:1)
dep=()
if ((${#indices[@]})); then
  list=$(IFS=,; echo "${indices[*]}")
  array=$(sbatch --parsable --export=ALL --array="$list" "${gres[@]}" "${task_opts[@]}" \
          --output="$out/logs/veil-regress-%A_%a.log" "${extra[@]}" "$here/regress.sbatch")
  array=${array%%;*}
  echo "array $array (tasks $list of 0-$((tasks - 1)))"
  dep=(--dependency=afterany:$array)
else
  echo "array none (every shard has a finished report)"
fi
merge_wait=()
((wait)) && merge_wait=(--wait)
set +e
merge=$(sbatch --parsable --export=ALL "${dep[@]}" --output="$out/logs/veil-regress-merge-%j.log" \
        "${merge_wait[@]}" "${extra[@]}" "$here/regress-merge.sbatch")
rc=$?
set -e
echo "merge ${merge%%;*}"
exit $rc
