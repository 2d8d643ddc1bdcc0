#!/bin/bash
# CI: a real single-node Slurm cluster (Debian's slurmctld, slurmd, munge), started as root
# without systemd in a private folder, runs a regression suite as a 4-task job array plus the
# merge job (submit-regress.sh), and checks that
#   1. the merged results.json equals an unsharded run's, case by case;
#   2. a task cancelled with scancel mid-run leaves no half-written file, the merge then fails
#      naming the missing shard, and a re-submission of only that shard (--resume) completes
#      the report, again equal to the unsharded one;
#   3. (once `veil render --frames` exists) a frame range rendered as an array equals the
#      same range rendered in one process, and so does it after one task's frames are deleted
#      and that task alone is re-submitted (VEIL_SHARDS=2 --array=1).
# The cluster is stopped in a trap: the daemons by their pid files, then every process that
# carries this cluster's SLURM_CONF (leftover slurmstepd and job processes).
#   scripts/slurm/ci-test.sh VEIL_BINARY [SUITE]
# SUITE defaults to the project's suite, tests/regression/suite.json (35 cases, about 20 s in
# one process on the 2-core CI machine); VEIL_CI_CASES="name ..." runs a subset of it instead.
# docs/cluster.md.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
veil=$(realpath "${1:?usage: $0 VEIL_BINARY [SUITE]}")
[[ $(id -u) == 0 ]] || { echo "ci-test: run as root (it starts slurmctld, slurmd, munged)" >&2; exit 1; }
for p in slurmctld slurmd munged sbatch scancel scontrol; do
  command -v $p >/dev/null || { echo "ci-test: $p missing (scripts/install-deps.sh --test installs Slurm and munge)" >&2; exit 1; }
done
py=/usr/bin/python3
t=$(mktemp -d /tmp/veil-slurm.XXXXXX)
chmod 755 "$t"
export SLURM_CONF=$t/slurm.conf
step() { echo "ci-test: [$((SECONDS))s] $*"; }

stop_cluster() {
  set +e
  scancel --quiet --user=root 2>/dev/null
  for f in "$t/slurmd.pid" "$t/slurmctld.pid" "$t/munge/munged.pid"; do
    [[ -s $f ]] && kill "$(cat "$f")" 2>/dev/null
  done
  sleep 1
  # slurmstepd can outlive slurmd: end every process started for this cluster (they carry
  # its SLURM_CONF in their environment), by pid.
  for env in /proc/[0-9]*/environ; do
    pid=${env#/proc/}; pid=${pid%/environ}
    [[ $pid == $$ || $pid == "$BASHPID" ]] && continue
    if { tr '\0' '\n' <"$env"; } 2>/dev/null | grep -qxF "SLURM_CONF=$SLURM_CONF"; then
      kill -9 "$pid" 2>/dev/null
    fi
  done
  for f in "$t/slurmd.pid" "$t/slurmctld.pid" "$t/munge/munged.pid"; do
    [[ -s $f ]] && kill -9 "$(cat "$f")" 2>/dev/null
  done
  rm -rf "$t"
}
on_exit() {
  rc=$?
  if ((rc)); then
    echo "ci-test: FAILED (status $rc); slurmctld / slurmd log tails:" >&2
    tail -n 15 "$t/slurmctld.log" "$t/slurmd.log" 2>/dev/null >&2
    for f in "$t"/run*/logs/*.log; do [[ -f $f ]] && { echo "== $f" >&2; tail -n 8 "$f" >&2; }; done
  fi
  stop_cluster
  exit $rc
}
trap on_exit EXIT
trap 'exit 130' INT TERM

# --- munge with a key of its own, on a private socket ---
mkdir -p "$t/munge"
if command -v mungekey >/dev/null; then
  mungekey --create --keyfile="$t/munge/munge.key" 2>/dev/null
else
  dd if=/dev/urandom bs=1 count=1024 of="$t/munge/munge.key" status=none
fi
chmod 600 "$t/munge/munge.key"
chown -R munge:munge "$t/munge"
chmod 711 "$t/munge"
runuser -u munge -- munged --key-file="$t/munge/munge.key" --socket="$t/munge/munge.socket" \
  --pid-file="$t/munge/munged.pid" --log-file="$t/munge/munged.log" \
  --seed-file="$t/munge/munged.seed"

# --- slurm.conf for this node only ---
host=$(hostname -s)
node=$(slurmd -C | head -n1)
cpus=$(sed -n 's/.* CPUs=\([0-9]*\).*/\1/p' <<<"$node")
mem=$(($(free -m | awk '/^Mem:/ {print $2}') * 9 / 10))
mkdir -p "$t/state" "$t/spool"
cat >"$SLURM_CONF" <<CONF
ClusterName=veilci
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$t/munge/munge.socket
StateSaveLocation=$t/state
SlurmdSpoolDir=$t/spool
SlurmctldPidFile=$t/slurmctld.pid
SlurmdPidFile=$t/slurmd.pid
SlurmctldLogFile=$t/slurmctld.log
SlurmdLogFile=$t/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MailProg=/bin/true
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MinJobAge=600
KillWait=5
MessageTimeout=20
NodeName=$host NodeAddr=127.0.0.1 $(sed -e 's/^NodeName=[^ ]* //' -e 's/ RealMemory=[0-9]*//' <<<"$node") RealMemory=$mem State=UNKNOWN
PartitionName=ci Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
step "starting slurmctld and slurmd ($cpus CPUs, ${mem} MB)"
slurmctld -i
slurmd
for ((i = 0; i < 150; ++i)); do
  state=$(sinfo -h -o %T 2>/dev/null | head -n1 || true)
  [[ $state == idle ]] && break
  sleep 0.2
done
[[ $state == idle ]] || { echo "ci-test: the node did not come up (state '$state')" >&2; exit 1; }
step "cluster up"

# --- the suite: the project's, or the subset VEIL_CI_CASES of it (scene paths made absolute) ---
suite=${2:-$root/tests/regression/suite.json}
if [[ -z ${2:-} && -n ${VEIL_CI_CASES:-} ]]; then
  suite=$t/suite.json
  $py - "$root/tests/regression/suite.json" "$suite" $VEIL_CI_CASES <<'PY'
import json, os, re, sys
src, dst, names = sys.argv[1], sys.argv[2], sys.argv[3:]
text = "\n".join(l for l in open(src).read().splitlines() if not l.lstrip().startswith("//"))
doc = json.loads(text)
base = os.path.dirname(os.path.abspath(src))
cases = [c for c in doc["cases"] if c["name"] in names]
missing = sorted(set(names) - {c["name"] for c in cases})
if missing:
    sys.exit("ci-test: not in the project suite: " + ", ".join(missing))
for c in cases:
    c["scene"] = os.path.join(base, c.get("scene", doc.get("defaults", {}).get("scene", "")))
    if c.get("reference", "").endswith(".exr"):
        c["reference"] = os.path.join(base, c["reference"])
d = doc.get("defaults", {})
for k in ("scene", "reference"):
    if k in d:
        d[k] = os.path.join(base, d[k]) if (k == "scene" or d[k].endswith(".exr")) else d[k]
doc["cases"] = cases
doc["name"] = "veil image regression (CI Slurm subset)"
json.dump(doc, open(dst, "w"), indent=1)
print(f"ci-test: {len(cases)} cases of {src}")
PY
fi

# Compares the cases of two results.json files: name, pass/fail, error, every metric value.
same_results() {
  $py - "$1" "$2" <<'PY'
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
def key(r):
    return [(c["name"], c["passed"], c["error"],
             [(m["name"], m["value"], m["threshold"], m["passed"]) for m in c["metrics"]])
            for c in r["cases"]]
ka, kb = key(a), key(b)
if ka != kb:
    for x, y in zip(ka, kb):
        if x != y:
            print("ci-test: differs:", x, "vs", y)
    sys.exit(f"ci-test: {sys.argv[2]} is not {sys.argv[1]} case by case")
print(f"ci-test: {len(ka)} cases equal ({sys.argv[2]} vs {sys.argv[1]})")
PY
}
job_state() { scontrol -o show job "$1" | sed -n 's/.*JobState=\([A-Z_]*\).*ExitCode=\([0-9:]*\).*/\1 \2/p'; }

# --- 1. unsharded, then a 4-task array + merge ---
step "unsharded run"
s0=$SECONDS
"$veil" regress "$suite" -o "$t/single" >"$t/single.log" 2>&1 || { cat "$t/single.log"; exit 1; }
step "unsharded: $((SECONDS - s0)) s"
s0=$SECONDS
"$here/submit-regress.sh" --tasks 4 --cpus 1 --mem 2G --veil "$veil" --wait "$suite" "$t/run"
step "4-task array + merge: $((SECONDS - s0)) s"
same_results "$t/single/results.json" "$t/run/report/results.json"

# Scaling (VEIL_CI_SCALING=1, docs/cluster.md): wall time of arrays of 1, 2 and 4 tasks + merge.
if [[ ${VEIL_CI_SCALING:-0} == 1 ]]; then
  for n in 1 2 4; do
    s0=$SECONDS
    "$here/submit-regress.sh" --tasks $n --cpus 1 --mem 2G --veil "$veil" --wait "$suite" "$t/scale-$n" >/dev/null
    step "scaling: $n task(s) + merge: $((SECONDS - s0)) s"
  done
fi

# --- 2. a task cancelled mid-run, recovered by re-submission ---
step "fault: cancel a task mid-run"
out=$(SUITE=$suite "$here/submit-regress.sh" --tasks 4 --cpus 1 --mem 2G --veil "$veil" "$suite" "$t/run-fault")
echo "$out"
array=$(sed -n 's/^array \([0-9]*\).*/\1/p' <<<"$out")
merge=$(sed -n 's/^merge \([0-9]*\).*/\1/p' <<<"$out")
victim=
for ((i = 0; i < 1200; ++i)); do
  for k in 0 1 2 3; do
    # Running, one case finished, the shard not: cancel it now.
    if compgen -G "$t/run-fault/shard-$k/cases/*.json" >/dev/null &&
      [[ ! -e $t/run-fault/shard-$k/results.json ]]; then
      victim=$k
      break
    fi
  done
  [[ -n $victim ]] && break
  sleep 0.05
done
[[ -n $victim ]] || { echo "ci-test: no task was caught mid-run" >&2; exit 1; }
scancel "${array}_$victim"
step "cancelled ${array}_$victim"
for ((i = 0; i < 600; ++i)); do
  read -r st code <<<"$(job_state "$merge")"
  [[ $st == COMPLETED || $st == FAILED || $st == CANCELLED ]] && break
  sleep 0.5
done
[[ $st == FAILED ]] || { echo "ci-test: the merge after a cancelled task ended $st $code, expected FAILED" >&2; exit 1; }
grep -q "shard-$victim/results.json" "$t/run-fault/logs/"veil-regress-merge-"$merge".log ||
  { echo "ci-test: the merge log does not name the missing shard" >&2; exit 1; }
# No half-written file: every case file parses, no temporary is left, no report file.
$py - "$t/run-fault/shard-$victim" <<'PY'
import json, os, sys
d = sys.argv[1]
for root, _, files in os.walk(d):
    for f in files:
        if ".tmp" in f:
            sys.exit(f"ci-test: temporary left behind: {os.path.join(root, f)}")
        if root.endswith("cases") and f.endswith(".json"):
            json.load(open(os.path.join(root, f)))
if os.path.exists(os.path.join(d, "results.json")):
    sys.exit("ci-test: a cancelled shard has a results.json")
print(f"ci-test: cancelled shard: {sum(f.endswith('.json') for f in os.listdir(os.path.join(d, 'cases')))} case file(s), all complete")
PY
out=$("$here/submit-regress.sh" --tasks 4 --cpus 1 --mem 2G --veil "$veil" --resume --wait "$suite" "$t/run-fault")
echo "$out"
grep -q "^array [0-9]* (tasks $victim of 0-3)" <<<"$out" ||
  { echo "ci-test: --resume did not submit exactly shard $victim" >&2; exit 1; }
same_results "$t/single/results.json" "$t/run-fault/report/results.json"

# --- 3. a frame range as an array (once veil render has --frames) ---
frames_scene=$root/datasets/scenes/fire-sequence.json
if "$veil" render --help 2>/dev/null | grep -q -- '--frames' && [[ -f $frames_scene ]]; then
  step "frame range as a 2-task array"
  range=${VEIL_CI_FRAMES:-1-4}
  mkdir -p "$t/frames-one" "$t/frames"
  "$veil" render "$frames_scene" --frames "$range" --width 64 --height 48 \
    -o "$t/frames-one/f.####.exr" >"$t/frames-one.log" 2>&1 || { cat "$t/frames-one.log"; exit 1; }
  SCENE=$frames_scene FRAMES=$range PATTERN=$t/frames/f.####.exr VEIL=$veil \
    sbatch --wait --export=ALL --array=0-1 -c 1 --mem=2G --output="$t/frames/%A_%a.log" \
    "$here/render-frames.sbatch" --width 64 --height 48 >/dev/null
  same_frames() {
    local n=0 f
    for f in "$t/frames-one"/f.*.exr; do
      "$veil" compare "$t/frames/$(basename "$f")" "$f" --metric maxabs --fail 0 >/dev/null
      n=$((n + 1))
    done
    ((n > 0)) || { echo "ci-test: no frames were rendered" >&2; exit 1; }
    echo $n
  }
  n=$(same_frames)
  step "$n frames equal to the one-process render"
  # Partial re-submission (docs/cluster.md): the second task's frames removed, that task alone
  # submitted again with VEIL_SHARDS=2 --array=1 renders the same frames (and only those).
  second=("$t/frames"/f.*.exr)
  second=("${second[@]:$((${#second[@]} / 2))}")
  rm -f "${second[@]}"
  SCENE=$frames_scene FRAMES=$range PATTERN=$t/frames/f.####.exr VEIL=$veil VEIL_SHARDS=2 \
    sbatch --wait --export=ALL --array=1 -c 1 --mem=2G --output="$t/frames/resubmit-%A_%a.log" \
    "$here/render-frames.sbatch" --width 64 --height 48 >/dev/null
  for f in "${second[@]}"; do
    [[ -f $f ]] || { echo "ci-test: the re-submitted task did not render $f" >&2; exit 1; }
  done
  grep -q "slice 1 of 2" "$t/frames"/resubmit-*.log ||
    { echo "ci-test: the re-submitted task did not render slice 1 of 2" >&2; exit 1; }
  n=$(same_frames)
  step "re-submitted task 1 of 2: ${#second[@]} frames rendered again, all $n equal"
else
  step "frame range: skipped (this veil render has no --frames)"
fi
step "passed"
