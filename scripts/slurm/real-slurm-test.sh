#!/usr/bin/env bash
# Runs a study through a real one-node Slurm cluster that it starts itself, and checks the result:
#
#   scripts/slurm/real-slurm-test.sh        exit 0: the campaign merged and equals an unsharded run
#
# 1. Installs Debian's `slurm-wlm` and `munge` with apt-get when slurmctld is missing. Where that
#    cannot be done (not root, no apt-get, the install fails) it prints a line starting
#    `real-slurm-test: SKIP:` with the reason and exits 0; it needs root to run slurmd.
# 2. Starts its own munged (own key and socket), slurmctld and slurmd from a slurm.conf it writes
#    into a temporary folder, on free ports, for the node `hostname -s` as `slurmd -C` describes
#    it (nothing under /etc is written; clients find the cluster through SLURM_CONF), with
#    MaxArraySize=3 (array indices 0..2).
# 3. Runs a small study (studies/smoke.toml with 6 speeds and 3 s records: 18 jobs, 6
#    reference runs) unsharded, then through submit.sh as references job + array of 2 shards
#    (1 CPU each) + afterok merge; requeues shard 1 while it runs (after it saved a job) and
#    restarts it (`scontrol update StartTime=now`: a requeued job is held ~120 s otherwise);
#    checks that the requeued task resumed its saved jobs and kept its log (--open-mode=append);
#    waits for the merge; compares the merged file with the unsharded run job by job
#    (compare-results.py: every dataset and attribute but the timings); resubmits the finished
#    shard 0 and checks that it is a no-op (its file unchanged).
#    Then packing: checks that Slurm refuses `--array=0-11` under MaxArraySize=3 and that
#    `submit.sh --dry-run --max-submit 4` packs into 2 tasks and prints 3 sbatch lines; submits
#    studies/smoke.toml (12 jobs, 4 reference runs) asking for 12 tasks with --throttle 2, checks
#    that submit.sh read MaxArraySize=3 and packed the jobs into 3 array tasks of 4 (shards i/3,
#    ArrayTaskThrottle=2), and compares the merged file with an unsharded run of it.
# 4. Prints the wall times and the CPU time of every step against the unsharded run.
# On exit it cancels its jobs and stops the daemons it started (by their PID files, slurmctld
# first), and removes its folder (kept, and named, when the test failed).
#
# Uses target/release/rotorsweep (built if needed) or $ROTORSWEEP_BIN, and the Python of .venv
# (scripts/python-test makes it), $PYTHON or python3 for h5py.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
t_start=$(date +%s.%N)
# Only the cluster started here: no site's settings (SLURM_CONF, SBATCH_PARTITION, a job's own
# SLURM_* when run inside one) may reach its commands, and its cleanup cannot touch a site's jobs.
while read -r v; do unset "$v"; done < <(compgen -e | grep -E '^(SLURM|SBATCH|SQUEUE|SINFO|SCONTROL)_' || true)
say() { echo "real-slurm-test: $*"; }
skip() {
  say "SKIP: $*"
  exit 0
}
fail() {
  say "FAIL: $*" >&2
  exit 1
}
elapsed() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }'; }

# 1. The packages.
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  [ "$(id -u)" -eq 0 ] || skip "slurm-wlm and munge are not installed, and installing them needs root"
  command -v apt-get >/dev/null || skip "slurm-wlm and munge are not installed, and there is no apt-get"
  say "installing slurm-wlm munge (apt-get)"
  if ! { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
    --no-install-recommends slurm-wlm munge; } >/tmp/real-slurm-test-apt.log 2>&1; then
    tail -n 5 /tmp/real-slurm-test-apt.log
    skip "apt-get could not install slurm-wlm munge (log: /tmp/real-slurm-test-apt.log)"
  fi
fi
[ "$(id -u)" -eq 0 ] || skip "slurmd must run as root to start jobs; run this test as root"
for u in munge slurm; do
  id "$u" >/dev/null 2>&1 || fail "user $u missing (the munge and slurm-wlm packages create it)"
done

if [ -z "${ROTORSWEEP_BIN:-}" ]; then
  source "$root/scripts/bootstrap.sh"
  (cd "$root" && cargo build --release --quiet --bin rotorsweep)
  ROTORSWEEP_BIN="$root/target/release/rotorsweep"
fi
real_bin="$(realpath "$ROTORSWEEP_BIN")"
py="${PYTHON:-python3}"
[ -z "${PYTHON:-}" ] && [ -x "$root/.venv/bin/python" ] && py="$root/.venv/bin/python"
"$py" -c 'import h5py' 2>/dev/null || fail "$py has no h5py: run scripts/python-test first (it makes .venv)"

# 2. The cluster.
base="$(mktemp -d /tmp/rotorsweep-slurm.XXXXXX)"
chmod 0755 "$base"
mkdir -p "$base"/{munge,ctld,d,log,run,out,bin}
chown munge:munge "$base/munge"
chown slurm:slurm "$base/ctld" "$base/log"
started=() # PID files of the daemons this script started, in start order
ok=0

alive() { # a live process (a zombie is not: the init here reaps late)
  [ -r "/proc/$1/stat" ] && [ "$(awk '{ print $3 }' "/proc/$1/stat" 2>/dev/null)" != Z ]
}
stop_daemon() { # $1: PID file
  local pid
  pid=$(cat "$1" 2>/dev/null) || return 0
  alive "$pid" || return 0
  kill -TERM "$pid" 2>/dev/null || return 0
  for _ in $(seq 1 200); do
    alive "$pid" || return 0
    sleep 0.2
  done
  say "$(basename "$1" .pid) (PID $pid) did not stop in 40 s: SIGKILL"
  kill -KILL "$pid" 2>/dev/null || true
}
cleanup() {
  local rc=$?
  set +e
  if [ -n "${SLURM_CONF:-}" ] && [ -f "$base/run/slurmctld.pid" ]; then
    squeue -h -o %A 2>/dev/null | sort -u | xargs -r scancel 2>/dev/null
    for _ in $(seq 1 50); do
      [ -z "$(squeue -h -o %A 2>/dev/null)" ] && break
      sleep 0.2
    done
  fi
  # Only the daemons started here: slurmctld before slurmd (slurm-local.md), munged last.
  for f in "$base/run/slurmctld.pid" "$base/run/slurmd.pid" "$base/munge/munged.pid"; do
    for s in "${started[@]}"; do
      [ "$s" = "$f" ] && stop_daemon "$f"
    done
  done
  if [ "$ok" -eq 1 ] && [ "$rc" -eq 0 ]; then
    rm -rf "$base"
  else
    say "logs and files kept in $base" >&2
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

wait_for() { # $1: seconds, then a command; polls it every 0.1 s
  local n=$(($1 * 10))
  shift
  for _ in $(seq 1 "$n"); do
    "$@" && return 0
    sleep 0.1
  done
  return 1
}
free_port() { "$py" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

dd if=/dev/urandom of="$base/munge/munge.key" bs=1024 count=1 status=none
chown munge:munge "$base/munge/munge.key"
chmod 0400 "$base/munge/munge.key"
sock="$base/munge/munge.socket"
runuser -u munge -- /usr/sbin/munged --socket="$sock" --key-file="$base/munge/munge.key" \
  --pid-file="$base/munge/munged.pid" --log-file="$base/munge/munged.log" \
  --seed-file="$base/munge/munged.seed"
started+=("$base/munge/munged.pid")
wait_for 10 test -s "$base/munge/munged.pid" || fail "munged did not start (log: $base/munge/munged.log)"
munge -S "$sock" -n | unmunge -S "$sock" | grep -q 'STATUS: *Success' || fail "munge -n | unmunge failed"

host="$(hostname -s)"
# Array indices 0..2 only: below the 12 tasks the packed campaign asks for.
max_array_size=3
node="$(slurmd -C | sed -n '1p' | sed -E 's/ UpTime=.*//')"
case "$node" in NodeName=*) ;; *) fail "slurmd -C printed '$node'" ;; esac
cat >"$base/slurm.conf" <<EOF
ClusterName=rstest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=slurm
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sock
StateSaveLocation=$base/ctld
SlurmdSpoolDir=$base/d
SlurmctldPidFile=$base/run/slurmctld.pid
SlurmdPidFile=$base/run/slurmd.pid
SlurmctldLogFile=$base/log/slurmctld.log
SlurmdLogFile=$base/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
MailProg=/bin/true
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
DefMemPerCPU=1024
ReturnToService=2
EnforcePartLimits=ALL
MaxArraySize=$max_array_size
MinJobAge=600
KillWait=5
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$base/slurm.conf"
/usr/sbin/slurmctld
started+=("$base/run/slurmctld.pid")
wait_for 20 test -s "$base/run/slurmctld.pid" || fail "slurmctld did not start (log: $base/log/slurmctld.log)"
/usr/sbin/slurmd
started+=("$base/run/slurmd.pid")
wait_for 20 test -s "$base/run/slurmd.pid" || fail "slurmd did not start (log: $base/log/slurmd.log)"
node_idle() { sinfo -h -o %T 2>/dev/null | grep -q '^idle'; }
wait_for 30 node_idle || fail "the node is not idle: $(sinfo 2>&1) (logs: $base/log)"
say "cluster up in $(elapsed "$t_start") s: $(sinfo -h -o '%P %D %T %c CPUs %m MB' 2>&1)"

# 3. The study, unsharded.
# 15 s simulated per job: a shard (9 jobs) runs for a few seconds, so it saves several batches
# (a batch holds at most a second of finished runs) and a requeue finds part of them saved.
study="$base/study.toml"
sed -e "s|^scene = .*|scene = \"$root/studies/scenes/reference-roll.toml\"|" \
  -e 's|^"simulation.t_end_s" = .*|"simulation.t_end_s" = 15.0|' \
  -e 's|^values = \[12.0, 14.0, 16.0, 16.4\]|values = [10.0, 12.0, 14.0, 16.0, 16.4, 18.0]|' \
  "$root/studies/smoke.toml" >"$study"
{ grep -q '^"simulation.t_end_s" = 15.0' "$study" && grep -q '18.0]' "$study"; } ||
  fail "studies/smoke.toml changed: the test's edits of it no longer apply"
jobs=$("$real_bin" plan "$study" | sed -n -E '1s/^study .*: ([0-9]+) jobs$/\1/p')
[ "$jobs" = 18 ] || fail "the test study has $jobs jobs, not 18"

# Every rotorsweep run of the test through a wrapper that logs its CPU time (user + system).
cpu_log="$base/cpu.log"
cat >"$base/bin/rotorsweep" <<EOF
#!/usr/bin/env bash
"$real_bin" "\$@"
rc=\$?
times >"$cpu_log.\$\$" # in this shell: a pipe or \$(...) would time a subshell's children
echo "\$(awk 'NR == 2 { for (i = 1; i <= 2; i++) { split(\$i, t, /[ms]/); s += 60 * t[1] + t[2] } printf "%.3f", s }' "$cpu_log.\$\$") \$*" >>"$cpu_log"
rm -f "$cpu_log.\$\$"
exit \$rc
EOF
chmod +x "$base/bin/rotorsweep"
t0=$(date +%s.%N)
"$base/bin/rotorsweep" run "$study" -o "$base/unsharded.h5" --threads 1 2>"$base/unsharded.log" ||
  fail "the unsharded run failed: $(tail -n 3 "$base/unsharded.log")"
wall_unsharded=$(elapsed "$t0")

# The campaign.
outdir="$base/out"
t0=$(date +%s.%N)
cpus=$(sed -n -E 's/.* CPUs=([0-9]+).*/\1/p' <<<"$node")
sub=$(ROTORSWEEP_BIN="$base/bin/rotorsweep" REFERENCE_CPUS=$((cpus < 2 ? 1 : 2)) SBATCH_OPTS="--cpus-per-task=1 --time=10" \
  "$here/submit.sh" "$study" 2 "$outdir") || fail "submit.sh failed: $sub"
echo "$sub"
read -r refs array merge < <(sed -n -E 's/^submitted: references ([0-9]+) array ([0-9]+) merge ([0-9]+) .*/\1 \2 \3/p' <<<"$sub")
[ -n "${merge:-}" ] || fail "submit.sh did not print its job ids"
state() { squeue -h -t all -j "$1" -o %T 2>/dev/null | head -n 1; }

# Requeue shard 1 once it runs and has saved a job, then start it again at once.
task="${array}_1"
saved() { [ "$(state "$task")" = RUNNING ] && compgen -G "$outdir/shard-1.h5.parts/batch-*.journal" >/dev/null; }
wait_for 120 saved || fail "shard 1 never ran with a saved job (state $(state "$task"))"
n_saved=$(compgen -G "$outdir/shard-1.h5.parts/batch-*.journal" | wc -l)
scontrol requeue "$task" || fail "scontrol requeue $task failed"
say "requeued $task while running, $n_saved part files (batches of its 9 jobs) saved"
pending() { [ "$(state "$task")" = PENDING ]; }
wait_for 60 pending || fail "$task did not return to PENDING after the requeue (state $(state "$task"))"
restarted() {
  [ "$(state "$task")" != PENDING ] && return 0
  scontrol update JobId="$task" StartTime=now 2>/dev/null
  sleep 0.4
  return 1
}
wait_for 60 restarted || fail "$task did not start again after scontrol update StartTime=now"

done_state() { case "$(state "$1")" in COMPLETED | FAILED | CANCELLED | TIMEOUT | OUT_OF_MEMORY | NODE_FAIL) return 0 ;; *) return 1 ;; esac }
wait_for 600 done_state "$merge" || fail "the merge job did not end in 600 s (state $(state "$merge"))"
wall_campaign=$(elapsed "$t0")
for j in "$refs" "${array}_0" "${array}_1" "$merge"; do
  [ "$(state "$j")" = COMPLETED ] || fail "job $j ended $(state "$j"): $(cat "$outdir"/slurm-*.out)"
done

# 4. The checks.
log1="$outdir/slurm-${array}_1.out"
[ "$(grep -c '^shard 1/2 ' "$log1")" -eq 2 ] ||
  fail "$log1 does not hold both starts of the requeued task (--open-mode=append): $(cat "$log1")"
resumed=$(sed -n -E 's/.* \(([0-9]+) resumed\).*/\1/p' "$log1" | tail -n 1)
{ [ -n "$resumed" ] && [ "$resumed" -ge 1 ] && [ "$resumed" -lt 9 ]; } ||
  fail "the requeued shard did not resume part of its jobs: $(tail -n 2 "$log1")"
"$py" "$here/compare-results.py" "$base/unsharded.h5" "$outdir/study.h5" >"$base/compare.txt" ||
  fail "the merged file differs from the unsharded run (above)"
say "merged file equals the unsharded run: $(cat "$base/compare.txt")"

# Resubmitting a finished shard is a no-op.
sum0=$(sha256sum <"$outdir/shard-0.h5")
ROTORSWEEP_BIN="$base/bin/rotorsweep" STUDY="$study" N=2 OUTDIR="$outdir" REFERENCES="$outdir/references.h5" \
  sbatch --wait --export=ALL --array=0 --output="$outdir/slurm-again-%A_%a.out" "$here/study-array.sbatch" >/dev/null ||
  fail "resubmitting the finished shard 0 failed: $(cat "$outdir"/slurm-again-*.out)"
[ "$(sha256sum <"$outdir/shard-0.h5")" = "$sum0" ] || fail "resubmitting shard 0 changed its file"
grep -q '9 jobs, 9 ok, 0 failed (9 resumed)' "$outdir"/slurm-again-*.out ||
  fail "the resubmitted shard 0 did not find itself complete: $(cat "$outdir"/slurm-again-*.out)"
say "resubmitted finished shard 0: no-op, file unchanged"

# A study of more jobs than the cluster's arrays allow: studies/smoke.toml (12 jobs, 4 reference
# runs) asked for 12 tasks, one job each, under MaxArraySize=3. Slurm itself refuses such an
# array; submit.sh packs the jobs into 3 tasks of 4.
if sbatch --array=0-11 --hold --wrap=true >"$base/too-big.txt" 2>&1; then
  fail "Slurm accepted --array=0-11 under MaxArraySize=$max_array_size: $(cat "$base/too-big.txt")"
fi
say "Slurm refuses --array=0-11 under MaxArraySize=$max_array_size: $(tr '\n' ' ' <"$base/too-big.txt")"
small="$root/studies/smoke.toml"
small_jobs=$("$real_bin" plan "$small" | sed -n -E '1s/^study .*: ([0-9]+) jobs$/\1/p')
[ "$small_jobs" = 12 ] || fail "studies/smoke.toml has $small_jobs jobs, not 12"
"$base/bin/rotorsweep" run "$small" -o "$base/smoke-unsharded.h5" --threads 1 2>"$base/smoke-unsharded.log" ||
  fail "the unsharded run of smoke.toml failed: $(tail -n 3 "$base/smoke-unsharded.log")"
dry=$(ROTORSWEEP_BIN="$real_bin" "$here/submit.sh" --dry-run --tasks 12 --max-submit 4 "$small" "$base/dry") ||
  fail "submit.sh --dry-run failed: $dry"
grep -q '^chose: 2 tasks .*capped to 2 by the submit limit (4 jobs less 2 for references and merge)' <<<"$dry" ||
  fail "submit.sh --max-submit 4 did not pack into 2 tasks: $dry"
{ [ "$(grep -c '^sbatch ' <<<"$dry")" -eq 3 ] && [ ! -e "$base/dry" ]; } ||
  fail "submit.sh --dry-run did not print 3 sbatch lines, or made its OUTDIR: $dry"
say "dry run with --max-submit 4: $(grep '^chose: ' <<<"$dry")"
packed="$base/packed"
t0=$(date +%s.%N)
sub=$(ROTORSWEEP_BIN="$base/bin/rotorsweep" SBATCH_OPTS="--time=10" \
  "$here/submit.sh" --tasks 12 --throttle 2 "$small" "$packed") || fail "submit.sh (packed) failed: $sub"
echo "$sub"
grep -q "^cluster: MaxArraySize=$max_array_size," <<<"$sub" || fail "submit.sh did not read MaxArraySize=$max_array_size"
grep -q '^chose: 3 tasks (12 wanted: asked, capped to 3 by MaxArraySize), 4 jobs per task, 1 CPUs per task, throttle 2 at once: --array=0-2%2$' <<<"$sub" ||
  fail "submit.sh did not pack 12 jobs into 3 tasks of 4 with throttle 2"
read -r prefs parray pmerge < <(sed -n -E 's/^submitted: references ([0-9]+) array ([0-9]+) merge ([0-9]+) .*/\1 \2 \3/p' <<<"$sub")
[ -n "${pmerge:-}" ] || fail "submit.sh (packed) did not print its job ids"
throttled=$(scontrol show job "$parray" 2>/dev/null | grep -o 'ArrayTaskThrottle=[0-9]*' | sort -u)
[ "$throttled" = ArrayTaskThrottle=2 ] || fail "the array's throttle is '$throttled', not ArrayTaskThrottle=2"
wait_for 600 done_state "$pmerge" || fail "the packed campaign's merge did not end in 600 s (state $(state "$pmerge"))"
wall_packed=$(elapsed "$t0")
tasks=$(squeue -h -t all -r -j "$parray" -o %i | sort)
[ "$tasks" = "$(printf '%s\n' "${parray}_0" "${parray}_1" "${parray}_2")" ] ||
  fail "the packed array's tasks are not ${parray}_0..2: $tasks"
for j in "$prefs" "${parray}_0" "${parray}_1" "${parray}_2" "$pmerge"; do
  [ "$(state "$j")" = COMPLETED ] || fail "job $j ended $(state "$j"): $(cat "$packed"/slurm-*.out)"
done
for i in 0 1 2; do
  { grep -q "^shard $i/3 " "$packed/slurm-${parray}_$i.out" && grep -q ': 4 jobs, ' "$packed/slurm-${parray}_$i.out"; } ||
    fail "task $i did not run shard $i/3 with 4 jobs: $(cat "$packed/slurm-${parray}_$i.out")"
done
[ ! -e "$packed/shard-3.h5" ] || fail "a fourth shard file exists"
"$py" "$here/compare-results.py" "$base/smoke-unsharded.h5" "$packed/study.h5" >"$base/compare-packed.txt" ||
  fail "the packed campaign's merged file differs from the unsharded run (above)"
say "packed: 12 jobs in 3 array tasks of 4 (MaxArraySize=$max_array_size, throttle 2) in $wall_packed s; merged file equals the unsharded run: $(cat "$base/compare-packed.txt")"

# CPU: every run's user + system time, from the wrapper's log (the requeued task's killed first
# attempt is not in it: the kill ended the wrapper too).
cpu() { awk -v pat="$1" '$0 ~ pat { s += $1 } END { printf "%.2f", s }' "$cpu_log"; }
c_uns=$(cpu 'unsharded.h5')
c_refs=$(cpu 'references-only')
c_s0=$(awk '/shard-0.h5/ { print $1; exit }' "$cpu_log")
c_s1=$(awk '/shard-1.h5/ { print $1; exit }' "$cpu_log")
c_merge=$(cpu ' merge ')
total=$(awk -v a="$c_refs" -v b="$c_s0" -v c="$c_s1" -v d="$c_merge" 'BEGIN { printf "%.2f", a + b + c + d }')
say "CPU: unsharded $c_uns s (wall $wall_unsharded s); campaign: references $c_refs s + shard 0 $c_s0 s + shard 1 $c_s1 s (its resumed run) + merge $c_merge s = $total s"
ok=1
say "ok: $jobs jobs, 2 shards, requeue and resubmission; 12 jobs packed into 3 tasks under MaxArraySize=$max_array_size; campaign wall $wall_campaign s, packed campaign $wall_packed s, test wall $(elapsed "$t_start") s"
