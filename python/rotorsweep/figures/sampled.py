"""The figures of a sampled study (``[sample]``, docs/statistics.md): the distribution of each
output, each output against each input, and the sensitivity indices.

In: the report's ``samples`` table (per job that ended ok: ``job_id``, ``label``, on grid axes
each swept key's value, each sampled parameter's value under its first key, each output under
its name with the unit in it), its ``statistics`` table (``output``, ``mean``, ``q05``,
``q95``) and its ``sensitivity`` table (Saltelli: ``first_order`` and ``total`` with
``_low``/``_high``; Morris: ``mu_star`` and ``sigma`` with theirs), all computed by the Rust report (:mod:`.tables`). Out:

* ``histograms.png``: a histogram per output (√n bins, at least 5), the mean solid and the 5 %
  and 95 % quantiles dashed, n and the mean in the title;
* ``scatter.png``: a row per output, a column per input: each job a dot;
* ``sensitivity.png``: a panel per output: per parameter the first-order and total Sobol'
  indices (Saltelli), or μ* and σ of the elementary effects (Morris), as bars with their 95 %
  bootstrap intervals.

Which outputs: those of the chosen channel (``--channel``, default centre/vertical: an output
whose name holds a ``:SENSOR/DIR`` or ``:SENSOR`` part only for that sensor and direction) and
those of no channel (critical speeds, bending frequencies, a random wall's realised statistics),
that vary over the jobs; at most :data:`MAX_OUTPUTS`, those of a sensor first, then a random
wall's, then the rest. The histograms count the independent draws only (of a Saltelli design
the rows of A and B, as the statistics table); the scatter shows every job. The inputs of the scatter: the sampled
parameters, except a random field's seed (a key ending in ``.seed``: a seed is no quantity),
whose realised statistics (the outputs ``wall_…_mm``) take its place. Units are in the names.
On grid axes (``[sample]`` beside ``[[axes]]``, whose tables lead with the swept keys) the
histograms pool the grid points and draw no mean or quantile lines, each sensitivity bar
pair names its grid point, and the scatter has a column per swept key (a number key) too.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from ._common import figure, grid

#: Most outputs drawn (panels of the histograms and sensitivity figures, rows of the scatter).
MAX_OUTPUTS = 9
#: Most inputs (columns) of the scatter figure.
MAX_INPUTS = 6
#: The realised statistics of a random wall: inputs of the scatter, outputs elsewhere.
WALL_PREFIX = "wall_"
#: Columns of the samples table that are not values.
ID_COLUMNS = ("job_id", "label")


def table(doc: dict, name: str) -> pd.DataFrame | None:
    """The report table ``name`` of the document ``doc`` as a DataFrame (None without it)."""
    t = next((t for t in doc.get("tables", []) if isinstance(t, dict) and t.get("name") == name),
             None)
    if t is None or not t.get("rows"):
        return None
    return pd.DataFrame(t["rows"], columns=t["columns"])


def _of_channel(output: str, sensor: str, direction: str) -> bool:
    """Whether ``output`` is of no channel or of the chosen one (module doc)."""
    places = output.split(":")[1:]
    located = [p for p in places if not p.endswith("x") and not p.isdigit()]
    if not located:
        return True
    return all(p in (f"{sensor}/{direction}", sensor) for p in located)


def chosen_outputs(samples: pd.DataFrame, parameters: list[str], channel: str) -> list[str]:
    """The outputs drawn (module doc), in the table's order."""
    sensor, _, direction = channel.partition("/")
    out = []
    for c in samples.columns:
        if c in ID_COLUMNS or c in parameters:
            continue
        v = pd.to_numeric(samples[c], errors="coerce").to_numpy(dtype=float)
        v = v[np.isfinite(v)]
        if len(v) >= 2 and np.ptp(v) > 0 and _of_channel(c, sensor, direction):
            out.append(c)

    def rank(name: str) -> int:
        return 0 if ":" in name and not name.split(":")[1].isdigit() else \
            1 if name.startswith(WALL_PREFIX) else 2

    return sorted(out, key=rank)[:MAX_OUTPUTS]


def histograms(samples: pd.DataFrame, outputs: list[str], statistics: pd.DataFrame | None,
               study: str) -> Figure | None:
    """``histograms.png`` (module doc); None without outputs."""
    if not outputs:
        return None
    rows, cols = grid(len(outputs))
    fig = figure(figsize=(4.2 * cols, 3.0 * rows + 0.5))
    axes = fig.subplots(rows, cols, squeeze=False).ravel()
    # Of a sampled study on grid axes the statistics hold a row per output and grid point
    # (columns before ``output``): the histogram pools the points and draws no point's lines.
    pooled = statistics is not None and list(statistics.columns).index("output") > 0
    stats = None if statistics is None or pooled else statistics.set_index("output")
    for ax, name in zip(axes, outputs):
        v = pd.to_numeric(samples[name], errors="coerce").to_numpy(dtype=float)
        v = v[np.isfinite(v)]
        ax.hist(v, bins=max(5, int(math.sqrt(len(v)))), color="#90caf9", edgecolor="#1565c0")
        title = f"n = {len(v)}"
        if stats is not None and name in stats.index:
            s = stats.loc[name]
            ax.axvline(float(s["mean"]), color="k", lw=1.5, label="mean")
            for q in ("q05", "q95"):
                ax.axvline(float(s[q]), color="k", lw=1, ls="--",
                           label="5 %, 95 %" if q == "q05" else None)
            title += f", mean {float(s['mean']):.4g}"
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(name, fontsize=8)
        ax.set_ylabel("jobs")
    for ax in axes[len(outputs):]:
        ax.set_visible(False)
    if stats is not None:
        axes[0].legend(fontsize=7)
    fig.suptitle(f"{study}: distribution of the outputs")
    return fig


def scatter(samples: pd.DataFrame, inputs: list[str], outputs: list[str],
            study: str) -> Figure | None:
    """``scatter.png`` (module doc); None without inputs or outputs."""
    inputs = inputs[:MAX_INPUTS]
    outputs = [o for o in outputs if o not in inputs]
    if not inputs or not outputs:
        return None
    fig = figure(figsize=(2.8 * len(inputs) + 0.6, 2.3 * len(outputs) + 0.6))
    axes = fig.subplots(len(outputs), len(inputs), squeeze=False, sharex="col", sharey="row")
    for i, out in enumerate(outputs):
        y = pd.to_numeric(samples[out], errors="coerce").to_numpy(dtype=float)
        for j, inp in enumerate(inputs):
            x = pd.to_numeric(samples[inp], errors="coerce").to_numpy(dtype=float)
            ax = axes[i, j]
            ax.plot(x, y, ".", ms=3, alpha=0.6, color="#1565c0")
            if i == len(outputs) - 1:
                ax.set_xlabel(inp, fontsize=7)
            if j == 0:
                ax.set_ylabel(out, fontsize=7)
            ax.tick_params(labelsize=7)
    fig.suptitle(f"{study}: each output against each input ({len(samples)} jobs)")
    return fig


def sensitivity(indices: pd.DataFrame | None, outputs: list[str], study: str) -> Figure | None:
    """``sensitivity.png`` (module doc); None without the table or its outputs."""
    if indices is None:
        return None
    morris = "mu_star" in indices.columns
    bars = [("mu_star", "μ*"), ("sigma", "σ")] if morris else [
        ("first_order", "first order S"), ("total", "total S_T")]
    names = [o for o in outputs if o in set(indices["output"])]
    if not names:
        return None
    rows, cols = grid(len(names))
    fig = figure(figsize=(4.6 * cols, 3.2 * rows + 0.5))
    axes = fig.subplots(rows, cols, squeeze=False).ravel()
    for ax, name in zip(axes, names):
        t = indices[indices["output"] == name]
        # On grid axes a bar pair per parameter and grid point (the swept keys lead the table).
        swept = list(indices.columns)[:list(indices.columns).index("output")]
        ticks = [p.split(".")[-1] if len(p) > 18 else p for p in t["parameter"]]
        if swept:
            ticks = [f"{tick} @ " + ", ".join(f"{k.split('.')[-1]}={r[k]:.4g}" if isinstance(r[k], float)
                                              else f"{k.split('.')[-1]}={r[k]}" for k in swept)
                     for tick, (_, r) in zip(ticks, t.iterrows())]
        x = np.arange(len(t))
        width = 0.38
        for k, (col, label) in enumerate(bars):
            v = t[col].astype(float).to_numpy()
            lo = t[f"{col}_low"].astype(float).to_numpy()
            hi = t[f"{col}_high"].astype(float).to_numpy()
            err = np.vstack([np.clip(v - lo, 0, None), np.clip(hi - v, 0, None)])
            ax.bar(x + (k - 0.5) * width, v, width, yerr=err, capsize=3, label=label,
                   color=("#1565c0", "#ef6c00")[k])
        ax.set_xticks(x)
        ax.set_xticklabels(ticks, fontsize=7, rotation=20, ha="right")
        ax.set_title(name, fontsize=8)
        ax.axhline(0.0, color="k", lw=0.5)
        if not morris:
            ax.set_ylabel("share of the variance")
    for ax in axes[len(names):]:
        ax.set_visible(False)
    axes[0].legend(fontsize=7)
    what = "Morris elementary effects (95 % bootstrap)" if morris else \
        "Sobol' indices (95 % bootstrap)"
    fig.suptitle(f"{study}: {what}")
    return fig


def sampled_figures(doc: dict, channel: str, study: str) -> list[tuple[str, Figure | None]]:
    """The figures of a sampled study from the report document ``doc`` (module doc); none when
    it has no ``samples`` table."""
    samples = table(doc, "samples")
    if samples is None:
        return []
    parameters = [c for c in samples.columns
                  if c not in ID_COLUMNS and "." in c and ":" not in c]
    outputs = chosen_outputs(samples, parameters, channel)
    # On grid axes the swept keys' columns are inputs too (a text key's values are not drawn).
    inputs = [p for p in parameters if not p.endswith(".seed")
              and pd.to_numeric(samples[p], errors="coerce").notna().any()]
    inputs += [o for o in outputs if o.startswith(WALL_PREFIX)]
    return [
        ("histograms.png", histograms(samples[~samples["label"].str.split(", ").str[-1].str.startswith("AB_")],
                                      outputs,
                                      table(doc, "statistics"), study)),
        ("scatter.png", scatter(samples, inputs,
                                [o for o in outputs if not o.startswith(WALL_PREFIX)], study)),
        ("sensitivity.png", sensitivity(table(doc, "sensitivity"), outputs, study)),
    ]
