#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# CI stage: a real one-node Slurm cluster on this machine runs a batch as a 4-task job array plus
# the dependent merge job (tools/cluster/submit-batch.sh), and the merged summary must equal the
# summary of the same batch run unsharded; then 2 tuning workers (tools/cluster/tune.sbatch) as an
# array sharing one Optuna study. Installs Debian's slurm-wlm and munge when missing,
# generates a munge key and a slurm.conf in a temporary folder (no cgroups: process tracking by
# /proc, no task plugin, no accounting), starts munged, slurmctld and slurmd on localhost, and
# stops them again on exit. Needs root (the daemons run as root here) and coxswain-sim built:
#   COXSWAIN_SIM=build/tools/sim/app/coxswain-sim .ci/slurm.sh
set -euo pipefail
cd "$(dirname "$0")/.."
sim=$(realpath "${COXSWAIN_SIM:-build/tools/sim/app/coxswain-sim}")
test -x "$sim" || { echo "slurm stage: $sim is not built"; exit 1; }
# A small batch: 4 shards of 2 runs, no camera frames (a few seconds of CPU per run).
batch_args=(--kind obstacle --runs 8 --seed0 101 --no-camera)
t0=$(date +%s)
log() { echo "[slurm $(( $(date +%s) - t0 )) s] $*"; }

if ! command -v slurmctld > /dev/null || ! command -v munged > /dev/null ||
   ! /usr/bin/python3 -c "import optuna, yaml" 2> /dev/null; then
  log "installing slurm-wlm, munge and python3-optuna"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends slurm-wlm munge \
    python3-optuna python3-yaml > /dev/null
fi

work=$(mktemp -d /tmp/coxswain-slurm.XXXXXX)
chmod 755 "$work"
pids=()
cleanup() {
  set +e
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null; done
  for p in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$p" 2> /dev/null || break; sleep 0.1; done
  done
  if [[ -f "$work/munged.pid" ]]; then kill "$(cat "$work/munged.pid")" 2> /dev/null; fi
  if [[ -n "${KEEP_SLURM_WORK:-}" ]]; then echo "kept $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT

# munge: its own key, socket and pid file in the work folder (a system munged, if any, is left
# alone). munged insists that the key and its folders belong to the user it runs as.
mkdir -p "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 700 "$work/munge"
chmod 400 "$work/munge/munge.key"
munge_socket="$work/munge/munge.socket"
munged --force --key-file="$work/munge/munge.key" --socket="$munge_socket" \
  --pid-file="$work/munged.pid" --log-file="$work/munged.log" --seed-file="$work/munge/seed"
for _ in $(seq 50); do [[ -S "$munge_socket" ]] && break; sleep 0.1; done
munge --socket="$munge_socket" -n | unmunge --socket="$munge_socket" > /dev/null
log "munged up"

host=$(hostname -s)
cpus=$(nproc)
mkdir -p "$work/state" "$work/spool" "$work/log"
cat > "$work/slurm.conf" << CONF
ClusterName=coxswain-ci
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
AuthInfo=socket=$munge_socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SwitchType=switch/none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=ci Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES
CONF
# No cgroup.conf: proctrack/linuxproc and task/none need none.
export SLURM_CONF=$work/slurm.conf
slurmctld -i -D -f "$SLURM_CONF" > "$work/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$host" > "$work/log/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
  state=$(sinfo -h -N -o %t 2> /dev/null || true)
  [[ "$state" == idle* ]] && break
  sleep 0.2
done
if [[ "$state" != idle* ]]; then
  echo "slurm stage: the node never became idle (state '$state')"
  tail -n 30 "$work"/log/*
  exit 1
fi
log "slurmctld and slurmd up, node $host idle with $cpus CPUs"

# The unsharded batch, as the reference (in the background while the cluster works).
"$sim" batch "${batch_args[@]}" --jobs 1 > "$work/whole.jsonl" &
whole_pid=$!

out=$work/results
export COXSWAIN_SIM=$sim
ids=$(tools/cluster/submit-batch.sh 4 "$out" "${batch_args[@]}")
log "submitted: $ids"
merge_id=${ids##* }
for _ in $(seq 900); do
  [[ -z "$(squeue -h -o %i 2> /dev/null)" ]] && break
  sleep 0.2
done
wait "$whole_pid"
if [[ ! -f "$out/merged.jsonl" ]]; then
  echo "slurm stage: no merged result"
  scontrol show job "$merge_id" || true
  tail -n 20 "$out"/slurm-*.out "$work"/log/* || true
  exit 1
fi
ls "$out"
merged=$(tail -n 1 "$out/merged.jsonl")
whole=$(tail -n 1 "$work/whole.jsonl")
echo "merged:    $merged"
echo "unsharded: $whole"
if [[ "$merged" != *'"summary":true'* || "$merged" != "$whole" ]]; then
  echo "slurm stage: the merged summary differs from the unsharded batch"
  exit 1
fi
# Every run line too, sorted by seed.
diff <(head -n -1 "$out/merged.jsonl") <("$sim" merge "$work/whole.jsonl" | head -n -1)
log "merged summary of 4 Slurm array tasks equals the unsharded batch"

# Tuning workers as an array: 2 tasks share one Optuna study through a journal file; together
# they finish 4 trials (2 runs each).
store="journal:$work/tune/study.journal"
mkdir -p "$work/tune"
tune_id=$(sbatch --parsable --array=0-1 --output="$work/tune/slurm-%A_%a.out" \
  tools/cluster/tune.sbatch "$store" ci --params-json tools/tune/testdata/obstacle_params.json \
  --param avoidance.clearance_m:0.2:0.6 --param heading_pid.kp_per_deg:0.03:0.08 \
  --kind obstacle --no-camera --runs 2 --max-time 60 --max-trials 4 --startup-trials 2)
log "submitted tuning array ${tune_id%%;*}"
for _ in $(seq 900); do
  [[ -z "$(squeue -h -o %i 2> /dev/null)" ]] && break
  sleep 0.2
done
finished=$(/usr/bin/python3 - "$work/tune/study.journal" << 'PY'
import sys, warnings
import optuna
warnings.filterwarnings("ignore")
storage = optuna.storages.JournalStorage(optuna.storages.JournalFileStorage(sys.argv[1]))
study = optuna.load_study(study_name="ci", storage=storage)
print(len([t for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE]))
PY
)
workers=$(grep -l '^trial ' "$work"/tune/slurm-*.out | wc -l)
if (( finished < 4 || workers < 2 )); then
  echo "slurm stage: the tuning array finished $finished trials from $workers workers"
  tail -n 20 "$work"/tune/slurm-*.out
  exit 1
fi
log "2 tuning workers in the Slurm array shared one study: $finished trials"
