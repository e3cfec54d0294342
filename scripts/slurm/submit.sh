#!/usr/bin/env bash
# Submits a rotorsweep study to Slurm: when the study has reference runs, first one job that
# computes them once for the campaign (references.sbatch -> OUTDIR/references.h5); then an array
# of shard tasks (study-array.sbatch; task i runs `rotorsweep run --shard i/N`, the jobs whose
# index modulo N is i, on SLURM_CPUS_PER_TASK threads) with --dependency=afterok on it, which copy
# the references they need from that file; then the merge (merge.sbatch) with
# --dependency=afterok on the whole array, so it runs only when every task ended ok.
#
#   scripts/slurm/submit.sh [OPTIONS] STUDY [N] [OUTDIR]   e.g. scripts/slurm/submit.sh studies/smoke.toml 4 out
#
# OUTDIR defaults to out; STUDY OUTDIR (a second argument that is not a number) leaves N out.
#
# How many tasks: N (or --tasks N; --jobs-per-task K asks for ceil(jobs/K)); without either, one
# task per --task-minutes of estimated CPU (`rotorsweep plan`'s cost estimate on the task's
# CPUs; default 10 min: below that the task's start, plan and files cost more than they save).
# The tasks are then packed into what the cluster allows: at most the study's job count, at most
# MaxArraySize (`scontrol show config`; indices 0..MaxArraySize-1), and at most what the user's
# MaxSubmitJobs and GrpSubmitJobs leave (`scontrol show assoc_mgr`: limit minus jobs already
# queued, minus the references and merge jobs; every array task counts as a job). Before it
# submits, it prints what it read and chose: tasks, jobs per task, throttle, CPUs per task.
# Options:
#   --tasks N            tasks wanted (same as the N argument)
#   --jobs-per-task K    tasks wanted: ceil(jobs / K)
#   --task-minutes M     without N or K: one task per M minutes of estimated CPU (default 10)
#   --throttle P         at most P tasks run at once (sbatch --array=...%P; default 64; 0: none)
#   --cpus-per-task C    CPUs (= threads) per task (default: the -c/--cpus-per-task in
#                        SBATCH_OPTS, else 1)
#   --max-array-size M   use M instead of the cluster's MaxArraySize
#   --max-submit S       use S jobs instead of the MaxSubmitJobs budget read from the cluster
#                        (QOS and account limits are not read: if sbatch refuses the array with
#                        a job-submit-limit error, give the budget here)
#   --dry-run            print the choice and the sbatch command lines; submit nothing
#
# Results: OUTDIR/references.h5, OUTDIR/shard-<i>.h5, OUTDIR/study.h5 (all jobs), logs
# OUTDIR/slurm-*.out. The last line printed names the jobs: `submitted: references R array A
# merge M (T tasks ...)` (R is `none` for a study without reference runs).
# If a task fails (time limit, node failure), the merge is cancelled; the jobs that task saved
# are kept, and resubmitting just the failed tasks resumes them (a shard that had finished is a
# no-op); submit.sh prints this command with its N:
#   STUDY=... N=... OUTDIR=... REFERENCES=OUTDIR/references.h5 sbatch --export=ALL \
#     --array=<failed ids> --output='OUTDIR/slurm-%A_%a.out' scripts/slurm/study-array.sbatch
# then merge (N=... OUTDIR=... sbatch --export=ALL scripts/slurm/merge.sbatch).
# Build the binary first on a login node (scripts/rotorsweep --version builds it with the bundled
# HDF5; for a site HDF5 see study-array.sbatch), or point ROTORSWEEP_BIN at one. Extra sbatch
# options (partition, account, time, ...) for every job: SBATCH_OPTS="--partition=short
# --time=1:00:00"; the references job's CPUs: REFERENCE_CPUS (default 1; up to the study's
# number of reference runs is useful).
# Test the scripts' logic without Slurm: scripts/slurm/local-test.sh.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
usage() {
  awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"
  exit 2
}
die() {
  echo "submit.sh: $*" >&2
  exit 1
}
count() { [[ "$2" =~ ^[0-9]+$ ]] || die "$1 takes a whole number, not '$2'"; }

tasks_wanted="" per_task="" task_minutes=10 throttle=64 cpus="" max_array="" max_submit="" dry=0
args=()
while [ $# -gt 0 ]; do
  opt="$1"
  case "$opt" in
    --*=*) set -- "${opt%%=*}" "${opt#*=}" "${@:2}" && continue ;;
    -h | --help) usage ;;
    --dry-run) dry=1 && shift && continue ;;
    --) shift && args+=("$@") && break ;;
    --tasks | --jobs-per-task | --task-minutes | --throttle | --cpus-per-task | --max-array-size | --max-submit)
      [ $# -ge 2 ] || die "$opt needs a value"
      count "$opt" "$2" ;;
    -*) die "unknown option $opt (see --help)" ;;
    *) args+=("$opt") && shift && continue ;;
  esac
  case "$opt" in
    --tasks) tasks_wanted=$2 ;;
    --jobs-per-task) per_task=$2 ;;
    --task-minutes) task_minutes=$2 ;;
    --throttle) throttle=$2 ;;
    --cpus-per-task) cpus=$2 ;;
    --max-array-size) max_array=$2 ;;
    --max-submit) max_submit=$2 ;;
  esac
  shift 2
done
if [ "${#args[@]}" -lt 1 ] || [ "${#args[@]}" -gt 3 ]; then usage; fi
# STUDY OUTDIR without N: a second argument that is not a number is OUTDIR.
if [ "${#args[@]}" -eq 2 ] && ! [[ "${args[1]}" =~ ^[0-9]+$ ]]; then args=("${args[0]}" "" "${args[1]}"); fi
if [ -n "${args[1]:-}" ]; then
  count N "${args[1]}"
  [ -z "$tasks_wanted" ] || [ "$tasks_wanted" = "${args[1]}" ] || die "N ${args[1]} and --tasks $tasks_wanted differ"
  tasks_wanted=${args[1]}
fi
[ -z "$tasks_wanted" ] || [ -z "$per_task" ] || die "give N (--tasks) or --jobs-per-task, not both"
for v in "$tasks_wanted" "$per_task" "$task_minutes" "$cpus"; do
  [ "$v" != 0 ] || die "tasks, jobs per task, task minutes and CPUs must be >= 1"
done

# Absolute paths, so the jobs do not depend on the directory they start in.
STUDY="$(realpath "${args[0]}")"
OUTDIR="$(realpath -m "${args[2]:-out}")"
ROTORSWEEP_BIN="$(realpath -m "${ROTORSWEEP_BIN:-$root/target/release/rotorsweep}")"
[ -x "$ROTORSWEEP_BIN" ] || die "no binary at $ROTORSWEEP_BIN: build it first (scripts/rotorsweep --version)"
# shellcheck disable=SC2206 # SBATCH_OPTS is a list of options, split on blanks
sbatch_opts=(${SBATCH_OPTS:-})
if [ -z "$cpus" ]; then
  cpus=1
  for ((k = 0; k < ${#sbatch_opts[@]}; k++)); do
    case "${sbatch_opts[$k]}" in
      --cpus-per-task=*) cpus=${sbatch_opts[$k]#*=} ;;
      -c[0-9]*) cpus=${sbatch_opts[$k]#-c} ;;
      -c | --cpus-per-task) cpus=${sbatch_opts[$((k + 1))]:-1} ;;
    esac
  done
  count "the CPUs per task in SBATCH_OPTS" "$cpus"
fi

# Check the study (every job's scene) now, not after the queue wait; its job count and cost.
plan=$("$ROTORSWEEP_BIN" plan "$STUDY" --threads "$cpus")
sed -n 1,2p <<<"$plan"
jobs=$(sed -n -E '1s/^study .*: ([0-9]+) jobs$/\1/p' <<<"$plan")
[ -n "$jobs" ] || die "could not read the job count from the first line of rotorsweep plan: $(head -n 1 <<<"$plan")"
[ "$jobs" -ge 1 ] || die "the study has no jobs"
nrefs=$(sed -n -E 's/^reference runs: ([0-9]+)$/\1/p' <<<"$plan")
cpu_s=$(sed -n -E 's/^cost estimate: ([0-9]+) s CPU.*/\1/p' <<<"$plan")

# The cluster's limits.
cluster="no cluster limits read (no scontrol)"
site_array="" budget=""
if ! command -v scontrol >/dev/null; then
  [ "$dry" -eq 1 ] || die "no scontrol: run this where Slurm's commands are"
elif ! config=$(scontrol show config 2>/dev/null); then
  [ "$dry" -eq 1 ] || die "scontrol show config failed: is the cluster reachable?"
  cluster="no cluster limits read (scontrol show config failed)"
else
  site_array=$(sed -n -E 's/^MaxArraySize *= *([0-9]+).*/\1/p' <<<"$config")
  cluster="MaxArraySize=${site_array:-?}"
  # The user's association limits, as the controller holds them: `MaxSubmitJobs=L(U)` and
  # `GrpSubmitJobs=L(U)` (L the limit or N for none, U the jobs queued now) in its records.
  user="${USER:-$(id -un)}"
  budget=$(scontrol show assoc_mgr users="$user" flags=assoc 2>/dev/null | awk -v u="$user" '
    /^ *ClusterName=/ { mine = index($0, "UserName=" u "(") > 0 }
    mine {
      for (i = 1; i <= NF; i++)
        if (match($i, /^(Max|Grp)SubmitJobs=[0-9]+\([0-9]+\)$/)) {
          split(substr($i, index($i, "=") + 1), v, /[()]/)
          left = v[1] - v[2]
          if (best == "" || left < best) best = left
        }
    }
    END { print best }')
  cluster="$cluster, ${budget:+MaxSubmitJobs/GrpSubmitJobs leave $budget jobs}${budget:-no MaxSubmitJobs or GrpSubmitJobs for $user}"
fi
[ -z "$max_array" ] || { site_array=$max_array && cluster="$cluster; --max-array-size $max_array"; }
[ -z "$max_submit" ] || { budget=$max_submit && cluster="$cluster; --max-submit $max_submit"; }
[ "${site_array:-1}" -ge 1 ] || die "MaxArraySize=0: job arrays are disabled on this cluster"
others=1 # the merge job
[ -z "$nrefs" ] || others=2
if [ -n "$budget" ] && [ "$budget" -le "$others" ]; then
  die "the submit limit leaves $budget jobs: not enough for the references, one task and the merge"
fi

# Tasks wanted, then packed into the limits.
if [ -n "$tasks_wanted" ]; then
  wanted=$tasks_wanted why="asked"
elif [ -n "$per_task" ]; then
  wanted=$(((jobs + per_task - 1) / per_task)) why="$per_task jobs per task asked"
elif [ -n "$cpu_s" ]; then
  slice=$((task_minutes * 60 * cpus))
  wanted=$(((cpu_s + slice - 1) / slice)) why="$cpu_s s CPU estimated, one task per $task_minutes min on $cpus CPUs"
  [ "$wanted" -ge 1 ] || wanted=1
else
  wanted=$jobs why="no cost estimate from plan: one task per job"
fi
tasks=$wanted caps=""
cap() { # $1 limit, $2 name
  if [ -n "$1" ] && [ "$tasks" -gt "$1" ]; then
    tasks=$1 caps="$caps, capped to $1 by $2"
  fi
}
cap "$jobs" "the job count"
cap "$site_array" "MaxArraySize"
[ -z "$budget" ] || cap $((budget - others)) "the submit limit ($budget jobs less $others for references and merge)"
lo=$((jobs / tasks)) hi=$(((jobs + tasks - 1) / tasks))
per="$hi"
[ "$lo" = "$hi" ] || per="$lo-$hi"
range="0-$((tasks - 1))" thr="none"
if [ "$throttle" -gt 0 ] && [ "$throttle" -lt "$tasks" ]; then
  range="$range%$throttle" thr="$throttle at once"
fi
echo "cluster: $cluster"
echo "chose: $tasks tasks ($wanted wanted: $why$caps), $per jobs per task, $cpus CPUs per task, throttle $thr: --array=$range"

export STUDY OUTDIR ROTORSWEEP_BIN
export N=$tasks
if [ "$dry" -eq 0 ]; then
  mkdir -p "$OUTDIR"
  old=()
  for f in "$OUTDIR"/shard-*.h5 "$OUTDIR"/study.h5 "$OUTDIR"/references.h5; do
    if [ -e "$f" ]; then old+=("$f"); fi
  done
  if [ "${#old[@]}" -gt 0 ]; then
    die "$OUTDIR already holds results (${old[*]:0:3}${old[3]:+ ...}): remove them or choose another OUTDIR"
  fi
fi
# One sbatch: prints it under --dry-run (the id becomes DRY-<name>), else runs it and prints the
# job id (without the cluster name multi-cluster sites add: "id;cluster").
submit() { # $1 name, then the sbatch arguments
  local name=$1 id
  shift
  if [ "$dry" -eq 1 ]; then
    printf 'sbatch --parsable --export=ALL'
    printf ' %q' "$@"
    printf '\n'
    echo "DRY-$name"
  else
    id=$(sbatch --parsable --export=ALL "$@") || die "sbatch of the $name job failed"
    echo "${id%%;*}"
  fi
}
last() { tail -n 1 <<<"$1"; }
if [ "$dry" -eq 1 ]; then
  echo "dry run: with STUDY=$STUDY N=$N OUTDIR=$OUTDIR ROTORSWEEP_BIN=$ROTORSWEEP_BIN${nrefs:+ REFERENCES=$OUTDIR/references.h5} in the environment:"
fi
refs=none
after=()
if [ -n "$nrefs" ]; then
  export REFERENCES="$OUTDIR/references.h5"
  out=$(submit references "${sbatch_opts[@]}" --cpus-per-task="${REFERENCE_CPUS:-1}" \
    --output="$OUTDIR/slurm-references-%j.out" "$here/references.sbatch")
  [ "$dry" -eq 0 ] || head -n -1 <<<"$out"
  refs=$(last "$out")
  after=(--dependency="afterok:$refs" --kill-on-invalid-dep=yes)
else
  unset REFERENCES
fi
out=$(submit array "${sbatch_opts[@]}" --cpus-per-task="$cpus" "${after[@]}" --array="$range" \
  --output="$OUTDIR/slurm-%A_%a.out" "$here/study-array.sbatch")
[ "$dry" -eq 0 ] || head -n -1 <<<"$out"
array=$(last "$out")
out=$(submit merge "${sbatch_opts[@]}" --dependency="afterok:$array" --kill-on-invalid-dep=yes \
  --output="$OUTDIR/slurm-merge-%j.out" "$here/merge.sbatch")
[ "$dry" -eq 0 ] || head -n -1 <<<"$out"
merge=$(last "$out")
[ "$dry" -eq 0 ] || exit 0
ids="$array,$merge"
[ "$refs" = none ] || ids="$refs,$ids"
echo "watch: squeue -j $ids    cancel: scancel ${ids//,/ }"
resubmit=(STUDY="$STUDY" N="$N" OUTDIR="$OUTDIR" ROTORSWEEP_BIN="$ROTORSWEEP_BIN")
[ -z "$nrefs" ] || resubmit+=(REFERENCES="$REFERENCES")
resubmit+=(sbatch --export=ALL "${sbatch_opts[@]}" --cpus-per-task="$cpus" --array=IDS
  --output="$OUTDIR/slurm-%A_%a.out" "$here/study-array.sbatch")
echo "resubmit failed tasks (IDS: their indices, e.g. 3,17): $(printf '%q ' "${resubmit[@]}")"
echo "submitted: references $refs array $array merge $merge ($tasks tasks of $per jobs -> $OUTDIR/study.h5)"
