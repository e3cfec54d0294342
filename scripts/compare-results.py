"""Proves that two rotorsweep binaries give the same results (e.g. before and after a restructure
of src/ that must not change a bit): runs a fixed set of commands with each and compares what
they wrote and printed.

    python3 scripts/compare-results.py --before BIN_A --after BIN_B [--keep DIR]

In: two rotorsweep binaries. From the repository root (this script's ../), each binary runs the
fixed set below into its own scratch folder (a temporary folder, removed at the end; with
`--keep DIR` the folders DIR/before and DIR/after, kept). Needs h5py and numpy.

    run studies/smoke.toml -o smoke.h5
    report smoke.h5                          (markdown, all tables)
    report smoke.h5 --format json
    simulate studies/scenes/timing-case.toml -o timing.h5 --json
    linear studies/scenes/reference-roll.toml --speeds 5:25:3 -o linear.h5
    run studies/runup-jeffcott.toml -o runup.h5
    run studies/balancing.toml -o bal.h5
    balance bal.h5 --check                   (it does not write into bal.h5: its file is
    balance bal.h5 --check --json             compared as it is after these)
    import studies/measured/jeffcott-runup-synthetic.csv -o imp-runup.h5
    import studies/measured/jeffcott-critical-synthetic.csv -o imp-critical.h5

Out: each command's wall time and exit code per binary; then per HDF5 file the groups, datasets
and attributes compared and per command whether its standard output is the same; then either
the line `identical: N files, G groups, D datasets, A attributes, T text outputs` and exit code
0, or every difference and exit code 1. Every command must exit 0 with both binaries.

Compared (scripts/h5compare.py): the names of the files each side wrote; in every HDF5 file
every group, dataset and attribute and the names on both sides, values exactly (floats bit for
bit, NaN equal to NaN; text as text; compound tables column by column; dimension-scale
references by the path they point to); every command's standard output as text, the scratch
folder's path replaced by OUT.

Left out, because they measure the machine or the build, not the results:
- `cpu_time_s` and `wall_time_s`: attributes of every job and reference run, columns of
  /summary, keys of `simulate --json`, columns of `report --format json`'s `solver` and
  `stability` tables;
- `times_s`: the wall time per analysis inside the `json` attribute of `linear -o`'s
  /linear/<scene> (masked there; the rest of that JSON is compared as written);
- `model_build_s` of `simulate --json`; `relative` (CPU time over the cheapest job's) of the
  report's `solver` table; in the markdown report the columns `CPU time [s]` and `relative` and
  every number of seconds in a table cell (the stability matrix's CPU times), with the tables'
  padding (it follows the widths of those numbers);
- the file root's identity attributes: `command` (the binary's path, the scratch folder),
  `created_utc`, `host`, `threads`, `tool_version` (the build's version). The root's `shard`
  (0/1 here), study and scene texts, paths and digests are compared; `partial` and
  `merged_from` occur only in merged files;
- the run logs OUT.h5.log (timestamps, CPU times, jobs in completion order): named, not read;
  `run`'s progress lines go to standard error, which is not compared.
"""

import argparse
import contextlib
import difflib
import json
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py

sys.path.insert(0, str(Path(__file__).resolve().parent))
import h5compare  # noqa: E402  (beside this script, put on the path above)

ROOT = Path(__file__).resolve().parents[1]
TIMING = h5compare.TIMING  # run times: left out
IDENTITY = h5compare.IDENTITY  # who wrote the file when: left out
COMMANDS = [  # the binary's arguments ({out}: the scratch folder), and how stdout is read
    (["run", "studies/smoke.toml", "-o", "{out}/smoke.h5"], "text"),
    (["report", "{out}/smoke.h5"], "text"),
    (["report", "{out}/smoke.h5", "--format", "json"], "json"),
    (["simulate", "studies/scenes/timing-case.toml", "-o", "{out}/timing.h5", "--json"], "json"),
    (["linear", "studies/scenes/reference-roll.toml", "--speeds", "5:25:3", "-o",
      "{out}/linear.h5"], "text"),
    (["run", "studies/runup-jeffcott.toml", "-o", "{out}/runup.h5"], "text"),
    (["run", "studies/balancing.toml", "-o", "{out}/bal.h5"], "text"),
    (["balance", "{out}/bal.h5", "--check"], "text"),
    (["balance", "{out}/bal.h5", "--check", "--json"], "json"),
    (["import", "studies/measured/jeffcott-runup-synthetic.csv", "-o", "{out}/imp-runup.h5"],
     "text"),
    (["import", "studies/measured/jeffcott-critical-synthetic.csv", "-o",
      "{out}/imp-critical.h5"], "text"),
]
SECONDS = re.compile(r"(?<![\w.])\d+(?:\.\d+)?(?:e[-+]?\d+)? s\b")


def shown(args):
    """A command as printed: its arguments, outputs named without the scratch folder."""
    return " ".join(args).replace("{out}/", "")


def run_all(binary, out, side):
    """Runs COMMANDS with `binary` into the folder `out`; returns per command its exit code,
    standard output and standard error, and prints its wall time."""
    results = []
    for args, _ in COMMANDS:
        argv = [str(binary)] + [a.format(out=out) for a in args]
        t0 = time.perf_counter()
        p = subprocess.run(argv, cwd=ROOT, capture_output=True, text=True, check=False)
        print(f"{side:6}  {time.perf_counter() - t0:6.2f} s  exit {p.returncode}  {shown(args)}",
              flush=True)
        results.append((p.returncode, p.stdout, p.stderr))
    return results


def masked_text(text, kind, out):
    """Standard output as lines to compare: the scratch folder `out` as OUT, timings masked
    (module doc): JSON re-serialised with the timing keys' and columns' values masked, numbers
    as written (text that is not JSON as it is); in markdown tables each cell stripped of its
    padding."""
    text = text.replace(str(out), "OUT")
    if kind == "json":
        try:
            value = json.loads(text, parse_float=str, parse_int=str)
        except ValueError:
            return text.splitlines()
        return json.dumps(_mask_json(value), indent=1, ensure_ascii=False).splitlines()
    lines, header = [], None
    for line in text.splitlines():
        if not line.startswith("|"):
            lines.append(line)
            header = None
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        header = header or cells
        lines.append(" | ".join(
            "-" if set(c) == {"-"} else "<timing>" if h in TIMING and c != h else
            SECONDS.sub("<timing> s", c)
            for h, c in zip(header, cells)))
    return lines


def _mask_json(v):
    if isinstance(v, dict):
        masked = {k: "<timing>" if k in TIMING else _mask_json(u) for k, u in v.items()}
        if isinstance(v.get("columns"), list) and isinstance(v.get("rows"), list):
            hide = [i for i, c in enumerate(v["columns"]) if c in TIMING]
            masked["rows"] = [[("<timing>" if i in hide else _mask_json(c))
                               for i, c in enumerate(row)] for row in v["rows"]]
        return masked
    return [_mask_json(u) for u in v] if isinstance(v, list) else v


def compare_outputs(before, after, dirs, diffs):
    """Checks the exit codes and compares the masked standard outputs; returns how many
    outputs were compared."""
    for (args, kind), b, a in zip(COMMANDS, before, after):
        bad = [f"{side}: `{shown(args)}` exited {r[0]}: {r[2].strip()[-500:]}"
               for side, r in (("before", b), ("after", a)) if r[0] != 0]
        if bad:
            diffs += bad
            continue
        x, y = (masked_text(r[1], kind, d) for r, d in zip((b, a), dirs))
        if x != y:
            diff = list(difflib.unified_diff(x, y, "before", "after", lineterm="", n=1))
            diffs.append(f"stdout of `{shown(args)}` differs:\n" + "\n".join(diff[:40]))
        print(f"stdout  {'same' if x == y else 'DIFFERS'} ({len(x)} lines)  {shown(args)}")
    return len(COMMANDS)


def compare_files(dirs, diffs):
    """Compares the files the two sides wrote; returns the HDF5 files compared and the Tally."""
    names = [sorted(p.name for p in d.iterdir()) for d in dirs]
    for n in sorted(set(names[0]) ^ set(names[1])):
        diffs.append(f"{n}: written by {'before' if n in names[0] else 'after'} only")
    total, files = h5compare.Tally(), 0
    for n in sorted(set(names[0]) & set(names[1])):
        if not n.endswith(".h5"):
            continue
        try:
            with h5py.File(dirs[0] / n, "r") as a, h5py.File(dirs[1] / n, "r") as b:
                d, t = h5compare.compare(a, b, f"{n}:/", skip=TIMING, skip_columns=TIMING,
                                         skip_top_attrs=IDENTITY, sides=("before", "after"))
        except OSError as e:
            diffs.append(f"{n}: not readable as HDF5: {e}")
            continue
        diffs += d
        total.add(t)
        files += 1
        print(f"{n:18} {t.groups:5} groups, {t.datasets:5} datasets, {t.attributes:6} attributes"
              f" compared{f', {len(d)} differences' if d else ''}")
    return files, total


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", required=True, type=Path, help="rotorsweep binary: the baseline")
    ap.add_argument("--after", required=True, type=Path, help="rotorsweep binary to check")
    ap.add_argument("--keep", type=Path, help="keep the outputs in DIR/before and DIR/after")
    opts = ap.parse_args()
    for b in (opts.before, opts.after):
        if not b.is_file():
            ap.error(f"{b}: no such file")
    with contextlib.ExitStack() as stack:
        if opts.keep:
            base = opts.keep.resolve()
            if (base / "before").exists() or (base / "after").exists():
                ap.error(f"{base}/before or {base}/after exists; give a new --keep folder")
        else:
            base = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="compare-")))
        dirs = (base / "before", base / "after")
        for d in dirs:
            d.mkdir(parents=True)
        t0 = time.perf_counter()
        before = run_all(opts.before.resolve(), dirs[0], "before")
        after = run_all(opts.after.resolve(), dirs[1], "after")
        diffs = []
        texts = compare_outputs(before, after, dirs, diffs)
        files, t = compare_files(dirs, diffs)
        print(f"total {time.perf_counter() - t0:.1f} s" +
              (f"; outputs kept in {base}" if opts.keep else ""))
    if diffs:
        print("\n".join(diffs), file=sys.stderr)
        print(f"DIFFERENT: {len(diffs)} differences", file=sys.stderr)
        sys.exit(1)
    print(f"identical: {files} files, {t.groups} groups, {t.datasets} datasets, "
          f"{t.attributes} attributes, {texts} text outputs")


if __name__ == "__main__":
    main()
