#!/usr/bin/env bash
# Submits a rotorsweep study to Slurm: when the study has reference runs, first one job that
# computes them once for the campaign (references.sbatch -> OUTDIR/references.h5); then an array
# of N shard tasks (study-array.sbatch) with --dependency=afterok on it, which copy the references
# they need from that file; then the merge (merge.sbatch) with --dependency=afterok on the whole
# array, so it runs only when every shard ended ok. If a task fails (time limit, node failure), the
# merge is cancelled; the jobs that task saved are kept, and resubmitting just the failed tasks
# resumes them (a shard that had finished is a no-op):
#   STUDY=... N=... OUTDIR=... REFERENCES=OUTDIR/references.h5 sbatch --export=ALL \
#     --array=<failed ids> --output='OUTDIR/slurm-%A_%a.out' scripts/slurm/study-array.sbatch
# then merge (merge.sbatch with N and OUTDIR, or rotorsweep merge OUTDIR/shard-*.h5 -o OUTDIR/study.h5).
#
#   scripts/slurm/submit.sh STUDY [N] [OUTDIR]      e.g. scripts/slurm/submit.sh studies/smoke.toml 4 out
#
# Results: OUTDIR/references.h5, OUTDIR/shard-<i>.h5, OUTDIR/study.h5 (all jobs), logs
# OUTDIR/slurm-*.out. The last line printed names the jobs: `submitted: references R array A
# merge M` (R is `none` for a study without reference runs).
# Build the binary first on a login node (scripts/rotorsweep --version builds it with the bundled
# HDF5; for a site HDF5 see study-array.sbatch), or point ROTORSWEEP_BIN at one. Extra sbatch
# options (partition, account, time, CPUs per shard, ...) for every job:
# SBATCH_OPTS="--partition=short --time=1:00:00 --cpus-per-task=4"; the references job's CPUs:
# REFERENCE_CPUS (default 1; up to the study's number of reference runs is useful).
# Test the scripts' logic without Slurm: scripts/slurm/local-test.sh.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
[ $# -ge 1 ] || { awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 2; }

# Absolute paths, so the jobs do not depend on the directory they start in.
STUDY="$(realpath "$1")"
N="${2:-4}"
OUTDIR="$(realpath -m "${3:-out}")"
ROTORSWEEP_BIN="$(realpath -m "${ROTORSWEEP_BIN:-$root/target/release/rotorsweep}")"
export STUDY N OUTDIR ROTORSWEEP_BIN
[ -x "$ROTORSWEEP_BIN" ] || { echo "no binary at $ROTORSWEEP_BIN: build it first (scripts/rotorsweep --version)" >&2; exit 1; }
[ "$N" -ge 1 ] || { echo "N must be >= 1" >&2; exit 1; }

# Check the study (every job's scene) now, not after the queue wait.
plan=$("$ROTORSWEEP_BIN" plan "$STUDY")
sed -n 1,2p <<<"$plan"
nrefs=$(sed -n -E 's/^reference runs: ([0-9]+)$/\1/p' <<<"$plan")
mkdir -p "$OUTDIR"
old=()
for f in "$OUTDIR"/shard-*.h5 "$OUTDIR"/study.h5 "$OUTDIR"/references.h5; do
  if [ -e "$f" ]; then old+=("$f"); fi
done
if [ "${#old[@]}" -gt 0 ]; then
  echo "$OUTDIR already holds results (${old[*]}): remove them or choose another OUTDIR" >&2
  exit 1
fi
refs=none
after=()
if [ -n "$nrefs" ]; then
  export REFERENCES="$OUTDIR/references.h5"
  # shellcheck disable=SC2086 # SBATCH_OPTS is a list of options
  refs=$(sbatch --parsable --export=ALL ${SBATCH_OPTS:-} --cpus-per-task="${REFERENCE_CPUS:-1}" \
    --output="$OUTDIR/slurm-references-%j.out" "$here/references.sbatch")
  refs="${refs%%;*}" # "id;cluster" on multi-cluster sites
  after=(--dependency="afterok:$refs" --kill-on-invalid-dep=yes)
else
  unset REFERENCES
fi
# shellcheck disable=SC2086
array=$(sbatch --parsable --export=ALL ${SBATCH_OPTS:-} "${after[@]}" --array="0-$((N - 1))" \
  --output="$OUTDIR/slurm-%A_%a.out" "$here/study-array.sbatch")
array="${array%%;*}"
# shellcheck disable=SC2086
merge=$(sbatch --parsable --export=ALL ${SBATCH_OPTS:-} --dependency="afterok:$array" \
  --kill-on-invalid-dep=yes --output="$OUTDIR/slurm-merge-%j.out" "$here/merge.sbatch")
merge="${merge%%;*}"
ids="$array,$merge"
[ "$refs" = none ] || ids="$refs,$ids"
echo "watch: squeue -j $ids    cancel: scancel ${ids//,/ }"
echo "submitted: references $refs array $array merge $merge ($N shards -> $OUTDIR/study.h5)"
