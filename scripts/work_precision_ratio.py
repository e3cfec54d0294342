#!/usr/bin/env python3
"""CPU time at equal error from a work-precision study's results file (issue 13).

In: a ``rotorsweep run`` results file whose jobs have an error against a reference run
(``error_max_um``, the max runout error [µm]) and a CPU time (``cpu_time_s`` [s]), e.g. of
studies/work-precision-cvode.toml or studies/linear-unbalance-cvode.toml; target errors [µm].
Out: a markdown table on standard output, per physics (the jobs with the same values of the
varying keys that are not ``solver.*`` nor ``reduction.*``: one reference run each) and
integrator: the CPU time [s] at each target error and its ratio to the ``--against`` integrator's
(default cvode); and per physics the best of the others (the lowest CPU time at that error) over
it.

Method: an integrator's front is what plots.py's work-precision figure draws: its jobs that ended
ok, sorted by CPU time, each kept when it is more accurate than every cheaper one. The CPU time
at a target error E is interpolated linearly in (log error, log CPU) between the two front points
whose errors bracket E. Where every front point is more accurate than E, the cheapest job's CPU
time bounds it from above ("≤"); where none reaches E, there is no value ("not reached").

Usage: scripts/work_precision_ratio.py RESULTS.h5 [--errors 1,0.1] [--against cvode]
Exit codes: 1 unreadable or unsuitable results file, 64 usage.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))
import rotorsweep as rp  # noqa: E402


def front(cpu: np.ndarray, err: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The work-precision front: points sorted by CPU time (then error), each more accurate
    than every cheaper one."""
    order = np.lexsort((err, cpu))
    cpu, err = cpu[order], err[order]
    keep = err < np.concatenate(([np.inf], np.minimum.accumulate(err)[:-1]))
    return cpu[keep], err[keep]


def cpu_at(cpu: np.ndarray, err: np.ndarray, target: float) -> tuple[float, str]:
    """CPU time at error ``target`` on the front (cpu, err) (module doc): (value, kind) with kind
    "=" interpolated, "≤" bounded by the cheapest point, "none" not reached (value nan)."""
    cpu, err = front(np.asarray(cpu, float), np.asarray(err, float))
    if len(cpu) == 0 or err[-1] > target:
        return math.nan, "none"
    if err[0] <= target:
        return float(cpu[0]), "≤"
    # err falls along the front: the first point at or below the target and the one before.
    i = int(np.argmax(err <= target))
    x0, x1 = math.log(err[i - 1]), math.log(err[i])
    y0, y1 = math.log(cpu[i - 1]), math.log(cpu[i])
    y = y0 + (math.log(target) - x0) * (y1 - y0) / (x1 - x0)
    return math.exp(y), "="


def _text(value: float, kind: str) -> str:
    if kind == "none":
        return "not reached"
    return ("≤ " if kind == "≤" else "") + f"{value:.4g}"


def table(summary: pd.DataFrame, physics_keys: list[str], errors: list[float],
          against: str) -> str:
    """The markdown table of the module doc."""
    ok = summary[(summary["status"] == "ok") & (summary["error_max_um"] > 0)]
    groups = ok.groupby(physics_keys, sort=False) if physics_keys else [((), ok)]
    head = ["physics", "integrator"] + [f"CPU at {e:g} µm [s]" for e in errors] + [
        f"÷ {against} at {e:g} µm" for e in errors]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for key, jobs in groups:
        key = key if isinstance(key, tuple) else (key,)
        physics = ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}"
                            for k, v in zip(physics_keys, key)) or "all jobs"
        at = {name: [cpu_at(j["cpu_time_s"].to_numpy(float), j["error_max_um"].to_numpy(float), e)
                     for e in errors]
              for name, j in jobs.groupby("integrator", sort=False)}
        ref = at.get(against)
        ours = {n: v for n, v in at.items() if n != against}
        best = []
        for k in range(len(errors)):
            known = [(v[k][0], v[k][1], n) for n, v in ours.items() if v[k][1] != "none"]
            best.append(min(known) if known else (math.nan, "none", "–"))
        rows = list(at.items()) + [(f"best of the others ({', '.join(b[2] for b in best)})",
                                    [(b[0], b[1]) for b in best])]
        for name, vals in rows:
            ratios = []
            for k, (v, kind) in enumerate(vals):
                if ref is None or ref[k][1] != "=" or kind == "none" or name == against:
                    ratios.append("–")
                else:
                    ratios.append(("≤ " if kind == "≤" else "") + f"{v / ref[k][0]:.3g}")
            lines.append("| " + " | ".join([physics, name] + [_text(*x) for x in vals] + ratios)
                         + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("results", help="results file (HDF5) of rotorsweep run")
    ap.add_argument("--errors", default="1,0.1", help="target errors [µm], comma-separated")
    ap.add_argument("--against", default="cvode", help="the integrator the ratios divide by")
    try:
        a = ap.parse_args(argv)
    except SystemExit as e:
        return 64 if e.code else 0
    try:
        errors = [float(x) for x in a.errors.split(",")]
    except ValueError:
        print(f"--errors {a.errors!r}: expected numbers separated by commas", file=sys.stderr)
        return 64
    if not errors or not all(math.isfinite(e) and e > 0 for e in errors):
        print(f"--errors {a.errors!r}: every error must be a positive number", file=sys.stderr)
        return 64
    try:
        summary = rp.summary(a.results)
        varying = rp.varying_keys(a.results)
    except (OSError, KeyError, ValueError) as e:
        print(f"{a.results}: not a rotorsweep results file with a summary: {e}", file=sys.stderr)
        return 1
    if "error_max_um" not in summary or "cpu_time_s" not in summary:
        print(f"{a.results}: no errors against a reference run (the study has no [reference])",
              file=sys.stderr)
        return 1
    physics = [k for k in varying if not k.startswith(("solver.", "reduction."))]
    print(table(summary, physics, errors, a.against))
    return 0


if __name__ == "__main__":
    sys.exit(main())
