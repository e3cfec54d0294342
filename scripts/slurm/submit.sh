#!/usr/bin/env bash
# Submits a rotorsweep study to Slurm: an array of N shard tasks (study-array.sbatch), then the
# merge (merge.sbatch) with --dependency=afterok on the whole array, so it runs only when every
# shard ended ok. If a task fails (time limit, node failure), the merge is cancelled; the jobs
# that task saved are kept, and resubmitting just the failed tasks resumes them:
#   STUDY=... N=... OUTDIR=... sbatch --export=ALL --array=<failed ids> scripts/slurm/study-array.sbatch
# then merge (merge.sbatch with N and OUTDIR, or rotorsweep merge OUTDIR/shard-*.h5 -o OUTDIR/study.h5).
#
#   scripts/slurm/submit.sh STUDY [N] [OUTDIR]      e.g. scripts/slurm/submit.sh studies/smoke.toml 4 out
#
# Results: OUTDIR/shard-<i>.h5, OUTDIR/study.h5 (all jobs), logs OUTDIR/slurm-*.out.
# Build the binary first on a login node (scripts/rotorsweep --version builds it with the bundled
# HDF5; for a site HDF5 see study-array.sbatch), or point ROTORSWEEP_BIN at one. Extra sbatch
# options (partition, account, time, ...) for both jobs: SBATCH_OPTS="--partition=short --time=1:00:00".
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
mkdir -p "$OUTDIR"
old=()
for f in "$OUTDIR"/shard-*.h5 "$OUTDIR"/study.h5; do
  if [ -e "$f" ]; then old+=("$f"); fi
done
if [ "${#old[@]}" -gt 0 ]; then
  echo "$OUTDIR already holds results (${old[*]}): remove them or choose another OUTDIR" >&2
  exit 1
fi
# shellcheck disable=SC2086 # SBATCH_OPTS is a list of options
array=$(sbatch --parsable --export=ALL ${SBATCH_OPTS:-} --array="0-$((N - 1))" \
  --output="$OUTDIR/slurm-%A_%a.out" "$here/study-array.sbatch")
array="${array%%;*}" # "id;cluster" on multi-cluster sites
# shellcheck disable=SC2086
merge=$(sbatch --parsable --export=ALL ${SBATCH_OPTS:-} --dependency="afterok:$array" \
  --kill-on-invalid-dep=yes --output="$OUTDIR/slurm-merge-%j.out" "$here/merge.sbatch")
merge="${merge%%;*}"
echo "submitted: array job $array ($N shards), merge job $merge -> $OUTDIR/study.h5"
echo "watch: squeue -j $array,$merge    cancel: scancel $array $merge"
