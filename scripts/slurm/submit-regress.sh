#!/bin/bash
# Submits a veil regression suite as a Slurm job array plus its merge job (docs/cluster.md).
#   scripts/slurm/submit-regress.sh [options] SUITE OUT
# Options (anything after -- goes to both sbatch calls, e.g. -- --account=X --partition=Y):
#   --tasks N      array size = number of shards (default 4)
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
usage() { echo "usage: $0 [--tasks N] [--gpu] [--time T] [--mem M] [--cpus C] [--veil PATH] [--resume] [--wait] SUITE OUT [-- SBATCH-OPTIONS]" >&2; exit 2; }
pos=()
while (($#)); do
  case $1 in
    --tasks) tasks=${2:?}; shift 2 ;;
    --gpu) gpu=1; shift ;;
    --time) task_opts+=("--time=${2:?}"); shift 2 ;;
    --mem) task_opts+=("--mem=${2:?}"); shift 2 ;;
    --cpus) task_opts+=("--cpus-per-task=${2:?}"); shift 2 ;;
    --veil) veil=${2:?}; shift 2 ;;
    --resume) resume=1; shift ;;
    --wait) wait=1; shift ;;
    --) shift; extra=("$@"); break ;;
    -*) usage ;;
    *) pos+=("$1"); shift ;;
  esac
done
((${#pos[@]} == 2)) || usage
[[ $tasks =~ ^[1-9][0-9]*$ ]] || { echo "$0: --tasks '$tasks' is not a positive integer" >&2; exit 2; }
suite=$(realpath "${pos[0]}") out=$(realpath -m "${pos[1]}")
[[ -f $suite ]] || { echo "$0: suite '$suite' does not exist" >&2; exit 1; }
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
