#!/usr/bin/env bash
# Checks the Slurm scripts' logic on this machine, without Slurm: runs references.sbatch (when
# the study has reference runs), study-array.sbatch as the N array tasks would (concurrently,
# each with its SLURM_ARRAY_TASK_ID), then merge.sbatch, then checks with h5py that the merged
# file holds every job of the study, each once, and a summary row per job. On a real Slurm:
# scripts/slurm/real-slurm-test.sh.
#
#   scripts/slurm/local-test.sh [STUDY] [N] [OUTDIR]     defaults: studies/smoke.toml 2 <temp dir>
#
# Uses target/release/rotorsweep (built if needed) or $ROTORSWEEP_BIN, and the Python of .venv
# (scripts/python-test makes it) if there is one.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
STUDY="$(realpath "${1:-$root/studies/smoke.toml}")"
N="${2:-2}"
OUTDIR="$(realpath -m "${3:-$(mktemp -d)/out}")"
if [ -z "${ROTORSWEEP_BIN:-}" ]; then
  source "$root/scripts/bootstrap.sh"
  (cd "$root" && cargo build --release --quiet --bin rotorsweep)
  ROTORSWEEP_BIN="$root/target/release/rotorsweep"
fi
SLURM_SUBMIT_DIR="$root"
SLURM_CPUS_PER_TASK="${SLURM_CPUS_PER_TASK:-1}"
export STUDY N OUTDIR ROTORSWEEP_BIN SLURM_SUBMIT_DIR SLURM_CPUS_PER_TASK
plan=$("$ROTORSWEEP_BIN" plan "$STUDY")
expected=$(sed -n -E '1s/^study .*: ([0-9]+) jobs$/\1/p' <<<"$plan")
[ -n "$expected" ] || { echo "local-test: could not read the job count from rotorsweep plan" >&2; exit 1; }
echo "local-test: $STUDY, $expected jobs in $N shards -> $OUTDIR"
mkdir -p "$OUTDIR"
if grep -q -E '^reference runs: [0-9]+$' <<<"$plan"; then
  export REFERENCES="$OUTDIR/references.h5"
  bash "$here/references.sbatch" >"$OUTDIR.references.log" 2>&1 ||
    { echo "local-test: the references step failed:" >&2; cat "$OUTDIR.references.log" >&2; exit 1; }
fi

pids=()
for ((i = 0; i < N; i++)); do
  SLURM_ARRAY_TASK_ID=$i SLURM_ARRAY_TASK_COUNT=$N bash "$here/study-array.sbatch" \
    >"$OUTDIR.task-$i.log" 2>&1 &
  pids+=($!)
done
for ((i = 0; i < N; i++)); do
  wait "${pids[$i]}" || { echo "local-test: task $i failed:" >&2; cat "$OUTDIR.task-$i.log" >&2; exit 1; }
done
bash "$here/merge.sbatch"

py=python3
[ -x "$root/.venv/bin/python" ] && py="$root/.venv/bin/python"
"$py" - "$OUTDIR" "$N" "$expected" <<'PY'
import sys
import h5py

outdir, n, expected = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
shard_jobs = []
for i in range(n):
    with h5py.File(f"{outdir}/shard-{i}.h5", "r") as f:
        assert f.attrs["shard"] == f"{i}/{n}", f.attrs["shard"]
        shard_jobs += list(f["jobs"])
with h5py.File(f"{outdir}/study.h5", "r") as f:
    jobs = sorted(f["jobs"])
    summary = f["summary"][()]
    index = sorted(int(x) for x in summary["job_index"])
    status = {s.decode() for s in summary["status"]}
    refs = sorted(f["references"])
    models = sorted(f["models"])
assert len(jobs) == expected, f"merged file has {len(jobs)} jobs, the study {expected}"
assert sorted(shard_jobs) == jobs, "the shards' jobs are not the merged file's"
assert len(set(shard_jobs)) == len(shard_jobs), "a job is in two shards"
assert index == list(range(expected)), index
assert sorted(x.decode() for x in summary["job_id"]) == jobs
print(f"local-test: ok: {len(jobs)} jobs ({n} shards), {len(refs)} references, "
      f"{len(models)} model(s), summary {len(summary)} rows, statuses {sorted(status)}")
PY
