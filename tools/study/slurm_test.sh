#!/usr/bin/env bash
# A real Slurm run of `flexmb study --slurm` (issue 26): a one-node cluster on this machine (munged,
# slurmctld and slurmd started here with a generated slurm.conf, every state file in a temporary
# folder, own ports and munge socket, so nothing of a system Slurm is touched), a 20-variant study
# of the cross-spring pivot submitted as a job array plus its dependent collect job, and the
# collected table compared with a local run's. The daemons it started are stopped on exit.
#
#   bash tools/study/slurm_test.sh <flexmb binary> <source folder>
#
# Installs slurm-wlm and munge (Debian packages) when they are missing and it runs as root. Exit 0:
# the tables are equal; 1: they differ or the jobs failed; 77: skipped (no packages and no way to
# install them, or the daemons cannot start here), with the reason on stderr. Runs in about a minute
# once the packages are there (CI: `bash tools/test.sh` runs it as the ctest study_slurm).
set -uo pipefail
flexmb=$(readlink -f "${1:?usage: slurm_test.sh <flexmb> <source folder>}")
src=$(readlink -f "${2:?usage: slurm_test.sh <flexmb> <source folder>}")
template="$src/datfiles/spatial/cross_spring_pivot_study.dat"
skip() { echo "slurm_test: SKIPPED: $*" >&2; exit 77; }
fail() { echo "slurm_test: FAILED: $*" >&2; exit 1; }

# ---- packages ------------------------------------------------------------------------------------
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null || ! command -v sbatch >/dev/null ||
   ! command -v munged >/dev/null; then
  [ "$(id -u)" = 0 ] ||
    skip "slurm-wlm and munge are not installed and this is not root (apt-get install -y slurm-wlm munge)"
  command -v apt-get >/dev/null || skip "slurm-wlm and munge are not installed and there is no apt-get"
  echo "slurm_test: installing slurm-wlm and munge" >&2
  export DEBIAN_FRONTEND=noninteractive
  { apt-get install -y --no-install-recommends slurm-wlm munge ||
    { apt-get update && apt-get install -y --no-install-recommends slurm-wlm munge; }; } >/dev/null 2>&1 ||
    skip "apt-get could not install slurm-wlm and munge (no network?)"
fi
[ "$(id -u)" = 0 ] || skip "slurmd must run as root to start jobs (SlurmdUser=root); run this as root"

# ---- a one-node cluster in a temporary folder --------------------------------------------------
work=$(mktemp -d /tmp/flexmb_slurm.XXXXXX)
chmod 755 "$work"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  for p in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$p" 2>/dev/null
  done
  if [ "${keep:-0}" = 1 ]; then echo "slurm_test: logs kept in $work" >&2; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

mkdir -p "$work/munge" "$work/state" "$work/spool" "$work/log"
chmod 700 "$work/munge"
# Munge: its own key and socket (the key is 1024 random bytes, as mungekey writes).
head -c 1024 /dev/urandom >"$work/munge/munge.key"
chmod 400 "$work/munge/munge.key"
socket="$work/munge/munge.socket"
munged --force --key-file="$work/munge/munge.key" --socket="$socket" --pid-file="$work/munge/munged.pid" \
  --log-file="$work/log/munged.log" --seed-file="$work/munge/munged.seed" 2>"$work/log/munged.err" ||
  { cat "$work/log/munged.err" >&2; skip "munged does not start here"; }
for _ in $(seq 50); do [ -S "$socket" ] && break; sleep 0.1; done
[ -S "$socket" ] || skip "munged made no socket"
pids+=("$(cat "$work/munge/munged.pid")")
munge --socket="$socket" -n </dev/null | unmunge --socket="$socket" >/dev/null 2>&1 || skip "munge does not work here"

host=$(hostname -s)
mem=$(awk '/^MemTotal:/ { printf "%d", $2 / 1024 * 0.9 }' /proc/meminfo)
# Ports of our own (another Slurm, or another run of this test, may hold the default ones).
port=$((20000 + ($$ % 20000)))
conf="$work/slurm.conf"
cat >"$conf" <<EOF
# One-node cluster for flexmb's study test (tools/study/slurm_test.sh)
ClusterName=flexmbtest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
MailProg=/bin/true
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
SlurmdParameters=config_overrides
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 RealMemory=$mem State=UNKNOWN
PartitionName=flexmb Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$conf"
slurmctld -f "$conf" -i 2>"$work/log/slurmctld.err" ||
  { cat "$work/log/slurmctld.err" "$work/log/slurmctld.log" >&2 2>/dev/null; skip "slurmctld does not start here"; }
for _ in $(seq 50); do [ -s "$work/slurmctld.pid" ] && break; sleep 0.1; done
[ -s "$work/slurmctld.pid" ] && pids+=("$(cat "$work/slurmctld.pid")")
slurmd -f "$conf" 2>"$work/log/slurmd.err" ||
  { cat "$work/log/slurmd.err" "$work/log/slurmd.log" >&2 2>/dev/null; skip "slurmd does not start here"; }
for _ in $(seq 50); do [ -s "$work/slurmd.pid" ] && break; sleep 0.1; done
[ -s "$work/slurmd.pid" ] && pids+=("$(cat "$work/slurmd.pid")")
# The node must come up idle.
up=0
for _ in $(seq 150); do
  state=$(sinfo -h -N -o %t 2>/dev/null | head -1)
  case "$state" in idle*|mix*|alloc*) up=1; break ;; esac
  sleep 0.2
done
if [ "$up" != 1 ]; then
  tail -20 "$work/log/slurmctld.log" "$work/log/slurmd.log" >&2 2>/dev/null
  skip "the Slurm node did not come up (state '${state:-none}')"
fi
echo "slurm_test: one-node cluster up (node $host, 2 CPUs, ports $port-$((port + 1)))" >&2

# ---- the study through Slurm and locally -------------------------------------------------------
cd "$work" || exit 1
args=(study "$template" --param t=0.1e-3:0.5e-3:20 --static --buckling --modes)
start=$(date +%s%N)
"$flexmb" "${args[@]}" --out slurm_run --slurm --tasks 4 >submit.txt 2>&1 ||
  { cat submit.txt >&2; fail "flexmb study --slurm"; }
cat submit.txt >&2
ids=$(sed -n 's/^submitted job array \([0-9]*\) .* collect job \([0-9]*\)$/\1,\2/p' submit.txt)
[ -n "$ids" ] || fail "no job ids in the output of --slurm"
done=0
for _ in $(seq 1500); do  # at most 150 s
  if [ -z "$(squeue -h -j "$ids" 2>/dev/null)" ] && [ -f slurm_run/study_run.txt ]; then done=1; break; fi
  sleep 0.1
done
wall_ms=$((($(date +%s%N) - start) / 1000000))
[ "$done" = 1 ] || { keep=1; squeue >&2; fail "the jobs did not finish within 150 s"; }
echo "slurm_test: 20 variants as 4 array tasks plus the collect job:" \
  "$((wall_ms / 1000)).$((wall_ms % 1000 / 100)) s from submission to table" >&2

"$flexmb" "${args[@]}" --out local_run --jobs 2 -q || fail "the local study"
if ! cmp -s slurm_run/study_summary.csv local_run/study_summary.csv; then
  keep=1
  diff slurm_run/study_summary.csv local_run/study_summary.csv | head >&2
  fail "the table collected through Slurm differs from the local run's"
fi
rows=$(($(wc -l <slurm_run/study_summary.csv) - 1))
ok=$(grep -c ',ok,' slurm_run/study_summary.csv)
[ "$rows" = 20 ] && [ "$ok" = 20 ] || fail "$rows rows, $ok ok (expected 20 and 20)"
ls slurm_run/slurm/task-*.out >/dev/null 2>&1 || fail "no task logs in slurm_run/slurm/"
echo "slurm_test: the Slurm table equals the local run's (20 variants, all ok)" >&2
exit 0
