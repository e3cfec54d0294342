"""Compares two rotorsweep study results files job by job: a merged campaign against an unsharded
run of the same study.

    python compare-results.py A.h5 B.h5

In: two results files (HDF5). Out: one line per difference on stderr and exit code 1, or a line
`same: ...` (the counts compared) and exit code 0.

Compared (by scripts/h5compare.py): every group, dataset and attribute under /jobs, /references,
/linear, /models and /analysis, and the /summary table, values exactly (floats bit for bit, NaN
equal to NaN; strings as text). Left out, because they measure the machine and not the results:
the `cpu_time_s` and `wall_time_s` attributes and summary columns, and the file's own attributes
(command line, creation time, threads, shard list, merge sources).
"""

import sys
from pathlib import Path

import h5py

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import h5compare  # noqa: E402  (scripts/, put on the path above)

TIMING = frozenset({"cpu_time_s", "wall_time_s"})
GROUPS = ["jobs", "references", "linear", "models", "analysis", "summary"]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    diffs = []
    with h5py.File(sys.argv[1], "r") as a, h5py.File(sys.argv[2], "r") as b:
        for g in GROUPS:
            if g not in a or g not in b:
                diffs.append(f"/{g}: missing in {sys.argv[1] if g not in a else sys.argv[2]}")
            else:
                diffs += h5compare.compare(a[g], b[g], f"/{g}", skip=TIMING, skip_columns=TIMING,
                                           sides=sys.argv[1:])[0]
        counts = ", ".join(f"{len(a[g])} {g}" for g in GROUPS[:-1] if g in a)
        rows = len(a["summary"]) if "summary" in a else 0
    if diffs:
        print("\n".join(diffs), file=sys.stderr)
        sys.exit(1)
    print(f"same: {counts}, summary {rows} rows")


if __name__ == "__main__":
    main()
