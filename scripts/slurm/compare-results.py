"""Compares two rotorsweep study results files job by job: a merged campaign against an unsharded
run of the same study.

    python compare-results.py A.h5 B.h5

In: two results files (HDF5). Out: one line per difference on stderr and exit code 1, or a line
`same: ...` (the counts compared) and exit code 0.

Compared: every group, dataset and attribute under /jobs, /references, /linear, /models and
/analysis, and the /summary table, values exactly (floats bit for bit, NaN equal to NaN; strings
as text). Left out, because they measure the machine and not the results: the `cpu_time_s` and
`wall_time_s` attributes and summary columns, and the file's own attributes (command line,
creation time, threads, shard list, merge sources).
"""

import sys

import h5py
import numpy as np

TIMING = {"cpu_time_s", "wall_time_s"}
GROUPS = ["jobs", "references", "linear", "models", "analysis"]


def same_value(x, y):
    x, y = np.asarray(x), np.asarray(y)
    if x.dtype.kind == "f" and y.dtype.kind == "f":
        return x.shape == y.shape and x.tobytes() == y.tobytes()
    if x.dtype.names or x.dtype.kind == "O" or y.dtype.kind == "O":
        return x.shape == y.shape and repr(x.tolist()) == repr(y.tolist())
    return x.shape == y.shape and np.array_equal(x, y)


def compare(a, b, path, diffs, skip_attrs=()):
    for k in sorted(set(a.attrs) | set(b.attrs)):
        if k in skip_attrs:
            continue
        if k not in a.attrs or k not in b.attrs:
            diffs.append(f"{path} attribute {k}: only in one file")
        elif not same_value(a.attrs[k], b.attrs[k]):
            diffs.append(f"{path} attribute {k}: {a.attrs[k]!r} vs {b.attrs[k]!r}")
    if isinstance(a, h5py.Group) != isinstance(b, h5py.Group):
        diffs.append(f"{path}: a group in one file, a dataset in the other")
    elif isinstance(a, h5py.Group):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                diffs.append(f"{path}/{k}: only in one file")
            else:
                compare(a[k], b[k], f"{path}/{k}", diffs, skip_attrs)
    elif not same_value(a[()], b[()]):
        diffs.append(f"{path}: data differs")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    diffs = []
    with h5py.File(sys.argv[1], "r") as a, h5py.File(sys.argv[2], "r") as b:
        for g in GROUPS:
            if g not in a or g not in b:
                diffs.append(f"/{g}: missing in {sys.argv[1] if g not in a else sys.argv[2]}")
            else:
                compare(a[g], b[g], f"/{g}", diffs, TIMING)
        sa, sb = a["summary"][()], b["summary"][()]
        if sa.dtype.names != sb.dtype.names or len(sa) != len(sb):
            diffs.append("/summary: other columns or rows")
        else:
            for col in sa.dtype.names:
                if col not in TIMING and not same_value(sa[col], sb[col]):
                    diffs.append(f"/summary column {col} differs")
        counts = ", ".join(f"{len(a[g])} {g}" for g in GROUPS if g in a)
    if diffs:
        print("\n".join(diffs), file=sys.stderr)
        sys.exit(1)
    print(f"same: {counts}, summary {len(sa)} rows")


if __name__ == "__main__":
    main()
