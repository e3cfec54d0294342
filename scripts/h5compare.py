"""Compares two HDF5 trees exactly: the shared core of scripts/compare-results.py (the results of
two rotorsweep binaries) and scripts/slurm/compare-results.py (a merged campaign against an
unsharded run).

In: two open h5py objects (files, groups or datasets) at the same path; the names to leave out
wherever they occur (as attributes, as keys of an attribute holding JSON text); the columns of
compound tables to leave out; the attributes of the starting object itself to leave out; the
two sides' names for the messages. Out: `compare` returns the differences, one line of text each
(none when the trees are equal), and a `Tally` of the groups, datasets and attributes compared.

As a command, `python3 scripts/h5compare.py A.h5 B.h5` compares two whole files as
compare-results.py does (timings and the file's identity attributes left out: TIMING and
IDENTITY below) and prints what it compared and every difference; exit code 0 when equal, 1
when not, 2 when a file cannot be read.

Equal means: the same member names and attribute names on both sides; a group where the other
side has a group; datasets and attributes of the same shape and type whose values are the same
bit for bit for numbers (so NaN equals NaN, and -0.0 differs from 0.0); text as text (bytes and
str of the same UTF-8 text are equal; JSON text with a left-out key is compared with that key's
value masked, everything else as written); compound tables column by column; object references
(the dimension scales' DIMENSION_LIST and REFERENCE_LIST) by the path of the object they point
to. A scale's REFERENCE_LIST (the datasets attached to it, with their dimension) is compared as a
set: its order is the order in which the attachments were made, which `rotorsweep merge` does
not keep and no reader uses. How a dataset is stored (chunks, filters) is not compared.
"""

import json
import sys
from dataclasses import dataclass

import h5py
import numpy as np


@dataclass
class Tally:
    """What was compared (both sides had it): groups (the starting group included), datasets,
    attributes."""

    groups: int = 0
    datasets: int = 0
    attributes: int = 0

    def add(self, other):
        self.groups += other.groups
        self.datasets += other.datasets
        self.attributes += other.attributes


def compare(a, b, path, skip=frozenset(), skip_columns=frozenset(), skip_top_attrs=frozenset(),
            sides=("A", "B")):
    """Differences between the h5py objects `a` and `b` (named `path` in the messages, their
    files `sides`) and the Tally of what was compared."""
    diffs, tally = [], Tally()
    ctx = (frozenset(skip), frozenset(skip_columns), sides, diffs, tally)
    _compare(a, b, path, frozenset(skip) | frozenset(skip_top_attrs), ctx)
    return diffs, tally


def _compare(a, b, path, skip_attrs, ctx):
    skip, skip_columns, sides, diffs, tally = ctx
    for k in sorted((set(a.attrs) | set(b.attrs)) - skip_attrs):
        if k not in a.attrs or k not in b.attrs:
            diffs.append(f"{path} attribute {k}: only in {sides[k not in a.attrs]}")
            continue
        tally.attributes += 1
        x, y = a.attrs[k], b.attrs[k]
        if isinstance(x, str) and isinstance(y, str):
            x, y = _masked_json(x, skip), _masked_json(y, skip)
        elif k == "REFERENCE_LIST":
            x, y = (sorted((f[r].name, int(d)) for r, d in v.tolist())
                    for v, f in ((x, a.file), (y, b.file)))
        d = value_difference(x, y, a.file, b.file)
        if d:
            diffs.append(f"{path} attribute {k}: {d}")
    if isinstance(a, h5py.Group) != isinstance(b, h5py.Group):
        diffs.append(f"{path}: a group in {sides[not isinstance(a, h5py.Group)]}, a dataset in "
                     f"{sides[isinstance(a, h5py.Group)]}")
    elif isinstance(a, h5py.Group):
        tally.groups += 1
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                diffs.append(f"{path.rstrip('/')}/{k}: only in {sides[k not in a]}")
            else:
                _compare(a[k], b[k], f"{path.rstrip('/')}/{k}", skip, ctx)
    else:
        tally.datasets += 1
        x, y = a[()], b[()]
        kept = [[n for n in v.dtype.names or () if n not in skip_columns] for v in (x, y)]
        if kept[0] != list(x.dtype.names or ()) and kept[0] == kept[1]:
            diffs += [f"{path} column {n}: {d}" for n in kept[0]
                      for d in [value_difference(x[n], y[n], a.file, b.file)] if d]
        else:
            d = value_difference(x, y, a.file, b.file)
            if d:
                diffs.append(f"{path}: {d}")


def _masked_json(text, keys):
    """`text` unchanged, or, when it is JSON holding one of `keys`, its JSON with those keys'
    values replaced by "<masked>", numbers kept as written (as strings), re-serialised."""
    try:
        value = json.loads(text, parse_float=str, parse_int=str, parse_constant=str)
    except ValueError:
        return text
    found = []

    def mask(v):
        if isinstance(v, dict):
            found.extend(k for k in v if k in keys)
            return {k: "<masked>" if k in keys else mask(u) for k, u in v.items()}
        return [mask(u) for u in v] if isinstance(v, list) else v

    masked = mask(value)
    return json.dumps(masked, ensure_ascii=False) if found else text


def value_difference(x, y, fx, fy):
    """None when the values `x` (read from the file `fx`) and `y` (from `fy`) are equal as the
    module doc says, else what differs, as text."""
    x, y = np.asarray(x), np.asarray(y)
    if x.shape != y.shape:
        return f"shape {x.shape} vs {y.shape}"
    if x.dtype.names or y.dtype.names:
        if x.dtype.names != y.dtype.names:
            return f"columns {x.dtype.names} vs {y.dtype.names}"
        diffs = [f"column {n}: {d}" for n in x.dtype.names
                 for d in [value_difference(x[n], y[n], fx, fy)] if d]
        return "; ".join(diffs) or None
    xi, yi = _items(x, fx), _items(y, fy)
    if xi is not None or yi is not None:
        if xi is None or yi is None:
            return f"type {x.dtype} vs {y.dtype}"
        differ = [i for i, (u, v) in enumerate(zip(xi, yi)) if u != v]
        return _count(differ, xi, yi, x.shape)
    if x.dtype != y.dtype:
        return f"type {x.dtype} vs {y.dtype}"
    size = max(x.dtype.itemsize, 1)
    xb = np.ascontiguousarray(x).reshape(-1).view(np.uint8).reshape(-1, size)
    yb = np.ascontiguousarray(y).reshape(-1).view(np.uint8).reshape(-1, size)
    differ = np.flatnonzero((xb != yb).any(axis=1)).tolist()
    return _count(differ, x.reshape(-1).tolist(), y.reshape(-1).tolist(), x.shape)


def _items(x, f):
    """The values of a text or object array as a flat list of plain values (text as str,
    references as the referenced object's path, nested arrays likewise), or None for a
    numeric array."""
    if x.dtype.kind not in "OSU":
        return None
    return [_plain(v, f) for v in x.reshape(-1)]


def _plain(v, f):
    if isinstance(v, bytes):
        return v.decode("utf-8", "backslashreplace")
    if isinstance(v, h5py.Reference):
        return f"-> {f[v].name}" if v else "-> null"
    if isinstance(v, np.ndarray):
        items = _items(v, f)
        return (v.shape, str(v.dtype), v.tobytes() if items is None else items)
    return v.item() if isinstance(v, np.generic) else v


def _count(differ, xs, ys, shape):
    if not differ:
        return None
    i = differ[0]
    at = [int(j) for j in np.unravel_index(i, shape)] if shape else []
    x, y = xs[i], ys[i]
    if isinstance(x, str) and isinstance(y, str):
        c = next((c for c, (u, v) in enumerate(zip(x, y)) if u != v), min(len(x), len(y)))
        at.append(f"character {c}")
        x, y = x[max(c - 50, 0):c + 50], y[max(c - 50, 0):c + 50]
    return (f"{len(differ)} of {max(len(xs), 1)} values differ, first at {at}: "
            f"{_short(x)} vs {_short(y)}")


def _short(v):
    s = repr(v)
    return s if len(s) <= 120 else s[:117] + "..."


# What the command leaves out: run times, and the attributes that say who wrote the file when.
TIMING = frozenset({"cpu_time_s", "wall_time_s", "times_s", "model_build_s", "relative",
                    "CPU time [s]"})
IDENTITY = frozenset({"command", "created_utc", "host", "threads", "tool_version"})


def main(argv):
    if len(argv) != 2:
        print("usage: python3 scripts/h5compare.py A.h5 B.h5", file=sys.stderr)
        return 2
    try:
        with h5py.File(argv[0], "r") as a, h5py.File(argv[1], "r") as b:
            diffs, tally = compare(a, b, "/", skip=TIMING, skip_columns=TIMING,
                                   skip_top_attrs=IDENTITY, sides=(argv[0], argv[1]))
    except OSError as e:
        print(f"cannot read: {e}", file=sys.stderr)
        return 2
    for d in diffs:
        print(d)
    print(f"{tally.groups} groups, {tally.datasets} datasets, {tally.attributes} attributes "
          f"compared: {'identical' if not diffs else f'{len(diffs)} differences'}")
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
