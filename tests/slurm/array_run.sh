#!/usr/bin/env bash
# A single-node Slurm cluster, started here and stopped on exit, runs a benchmark run as an
# `sbatch --array` of shards plus a merge job that depends on them (docs/scaling.md).
#   array_run.sh EITBENCH WORKDIR SHARDS RUN-ARGS...
# Writes the run into WORKDIR/run. Exit 77 (skip) when Slurm is not installed or will not start;
# otherwise the merge job's result: 0 when WORKDIR/run/results.json was written.
set -uo pipefail
eitbench=$1 work=$2 shards=$3
shift 3
for tool in slurmctld slurmd sbatch squeue sinfo scontrol; do
  command -v "$tool" > /dev/null || { echo "array_run.sh: $tool not installed"; exit 77; }
done
mkdir -p "$work/state" "$work/spool" "$work/logs"
host=$(hostname -s)
port=$((10000 + $$ % 20000))  # two ports a test run, below the kernel's ephemeral range
export SLURM_CONF=$work/slurm.conf
cat > "$SLURM_CONF" <<CONF
ClusterName=eitbench-test
SlurmctldHost=$host
AuthType=auth/none
CredType=cred/none
SlurmUser=$(id -un)
SlurmdUser=$(id -un)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
DependencyParameters=kill_invalid_depend
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF

stop() {
  scontrol shutdown > /dev/null 2>&1
  for pid in "$work/slurmctld.pid" "$work/slurmd.pid"; do
    [ -f "$pid" ] && kill "$(cat "$pid")" 2> /dev/null
  done
  sleep 1
}
trap stop EXIT
slurmctld -c > "$work/logs/start.log" 2>&1 && slurmd -c >> "$work/logs/start.log" 2>&1 || {
  echo "array_run.sh: Slurm would not start: $(cat "$work/logs/start.log")"
  exit 77
}
for _ in $(seq 60); do
  [ "$(sinfo -h -o %T 2> /dev/null)" = idle ] && break
  sleep 0.5
done
[ "$(sinfo -h -o %T 2> /dev/null)" = idle ] || {
  echo "array_run.sh: the node never came up: $(tail -3 "$work/slurmctld.log" "$work/slurmd.log")"
  exit 77
}

array=$(sbatch --parsable --array=0-$((shards - 1)) --cpus-per-task=1 \
  -o "$work/logs/shard-%a.out" \
  --wrap "'$eitbench' run $* --shard \$SLURM_ARRAY_TASK_ID/$shards --out '$work/run'") || exit 1
merge=$(sbatch --parsable --dependency=afterok:"$array" -o "$work/logs/merge.out" \
  --wrap "'$eitbench' merge '$work/run'") || exit 1
echo "array job $array, merge job $merge"
# A failed shard cancels the merge (kill_invalid_depend); the wait stays far below ctest's limit,
# so that this script, not ctest, stops the daemons.
for _ in $(seq 240); do
  [ -z "$(squeue -h 2> /dev/null)" ] && break
  sleep 1
done
[ -z "$(squeue -h 2> /dev/null)" ] || { echo "array_run.sh: jobs still queued after 240 s"; squeue; }
cat "$work"/logs/*.out
[ -f "$work/run/results.json" ]
