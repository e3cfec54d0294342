#!/usr/bin/env python3
"""PNG plots of a study's results file (``rotorsweep run STUDY -o OUT.h5``).

    python3 scripts/plots.py OUT.h5 [-o DIR] [--channel centre/vertical]

Writes into DIR (default: ``OUT-plots`` beside the file), each plot only when the file holds its
data, and prints the paths written:

* ``spectral_map[-<n>].png``: per speed sweep with a map (``/analysis/sweeps/<n>``), the runout
  amplitude [µm, log colour scale] over frequency [Hz] × speed [Hz], one panel per direction of
  the chosen sensor, with the roll's lines f = k·speed (k = 1…4) and the rollers' lines
  f = 0.92·k·speed;
* ``harmonics[-<n>].png``: per speed sweep, the amplitude of each of the study's orders over
  speed (log), one panel per direction of the chosen sensor;
* ``trial_mass.png``: the 1× amplitude change |A| − |A₀| and vector change |A − A₀| against the
  baseline jobs over speed (``/analysis/trial_mass``), one panel per sensor in the chosen
  direction, one pair of curves per trial setting;
* ``work_precision.png``: runout error against the reference [µm] over CPU time [s], log–log,
  one series per integrator (jobs that ended ok; the legend counts the failed ones);
* ``timing.png``: CPU time [s] per job, annotated with Newton iterations per step (≤ 12 jobs);
* ``stability.png``: when ``solver.integrator`` and other keys vary, a matrix integrator ×
  setting coloured by status, with the error [µm] and CPU time [s] in the cells;
* ``campbell.png``: the Campbell diagram of each linearised system (``/linear/<id>``, at most
  four panels): whirl frequencies [Hz] of the model on its linearised supports over spin speed
  [Hz], with the lines f = k·speed (k = 1…4) and the critical speeds.

The ``-<n>`` suffix (the sweep's number in the file) is added only when the file has several
sweeps. ``--channel SENSOR/DIR`` picks the sensor of the maps and harmonics and the direction of
the trial-mass panels. Importable: :func:`render` does the same and returns the paths. The
figures are drawn on Agg canvases of their own; matplotlib's global backend is left alone.
Exit code 1, with a message naming the file, when it is not a study results file.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import LogNorm, to_rgb
from matplotlib.figure import Figure
from matplotlib.patches import Patch

import rotorsweep_py as rp
from rotorsweep_py.loader import PathLike

#: Resolution of the PNG files [dots per inch].
DPI = 110
#: Directions of the runout channels, in panel order.
DIRECTIONS = ("vertical", "horizontal")
#: Roll harmonics drawn on the spectral maps (f = k · speed).
HARMONICS = (1, 2, 3, 4)
#: The rollers turn at 115/125 of the roll's speed (reference roll's scene): their lines lie at
#: f = 0.92 · k · speed.
ROLLER_RATIO = 0.92
#: Decades of amplitude below the map's maximum that the colour scale spans.
MAP_DECADES = 4
#: Most linearised systems drawn in the Campbell diagram (one panel each).
MAX_CAMPBELL_PANELS = 4
#: Largest study that gets a per-job timing bar chart.
MAX_TIMING_JOBS = 12
#: Fill colour of each job status.
STATUS_COLOURS = {"ok": "#9ccc65", "diverged": "#ef5350", "budget": "#ffb74d"}
MARKERS = "osD^v<>"


class PlotError(Exception):
    """The file is not a study results file, or the requested channel is not in it."""


def _figure(**kw: object) -> Figure:
    """A figure with constrained layout on an Agg canvas of its own."""
    fig = Figure(layout="constrained", **kw)
    FigureCanvasAgg(fig)
    return fig


def _save(fig: Figure, path: Path) -> Path:
    fig.savefig(path, dpi=DPI)
    return path


def check_results_file(path: PathLike) -> None:
    """Raises :class:`PlotError` naming ``path`` unless it is an HDF5 file written by
    ``rotorsweep run`` or ``merge`` (tool attribute "rotorsweep" and a ``/summary`` table)."""
    if not Path(path).is_file():
        raise PlotError(f"{path}: no such file")
    try:
        with h5py.File(path, "r") as f:
            tool = f.attrs.get("tool")
            has_summary = "summary" in f
    except OSError as e:
        raise PlotError(f"{path}: not an HDF5 file ({e})") from None
    if tool != "rotorsweep" or not has_summary:
        raise PlotError(
            f"{path}: not a rotorsweep study results file (no /summary table; "
            "`rotorsweep run STUDY -o OUT.h5` writes one)"
        )


def _format(value: object) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def settings(summary: pd.DataFrame, labels: pd.DataFrame, keys: list[str]) -> pd.Series:
    """A short text per job (index job_id, summary order) naming its values of the varying
    ``keys``: the label of each labelled axis among them (``labels`` as
    :func:`rotorsweep_py.job_labels` returns it), then ``key=value`` for every key that no shown
    label determines (a key is determined by a label when all jobs with that label share its
    value, as the other keys of a zipped axis do). "" for every job when nothing is left."""
    df = summary.set_index("job_id")
    shown = [k for k in labels.columns if k in keys]
    parts = [labels.loc[df.index, k].fillna("").astype(str) for k in shown]
    by_label = [df.groupby(p.to_numpy()) for p in parts]
    for k in keys:
        if not any(g[k].nunique(dropna=False).max() <= 1 for g in by_label):
            parts.append(k + "=" + df[k].map(_format))
    if not parts:
        return pd.Series("", index=df.index)
    return pd.concat(parts, axis=1).agg(lambda row: ", ".join(p for p in row if p), axis=1)


def _panels(data: dict[str, np.ndarray], sensor: str) -> list[str]:
    """The directions of ``sensor`` that ``data`` (a sweep's lines or maps) holds."""
    return [d for d in DIRECTIONS if f"{sensor}/{d}" in data]


def _sweep_title(study: str, what: str, sweep: rp.Sweep) -> str:
    return f"{study}: {what}" + (f"\n{sweep['fixed']}" if sweep["fixed"] else "")


def spectral_map(sweep: rp.Sweep, sensor: str, study: str) -> Figure | None:
    """The sweep's spectral map of ``sensor`` (amplitude [µm] over frequency [Hz] × speed [Hz]),
    one panel per direction on a shared log colour scale that spans :data:`MAP_DECADES` below the
    largest amplitude above the static offset (the 0 Hz bin and the next one, where the Hanning
    window spreads half of it, are left out of the scale and clipped to its top colour); None
    when the sweep has no map of that sensor or it is zero above those bins."""
    dirs = _panels(sweep["maps"], sensor)
    if not dirs or sweep["freq_hz"] is None:
        return None
    maps = [sweep["maps"][f"{sensor}/{d}"] for d in dirs]
    freq, speed = sweep["freq_hz"], sweep["speed_hz"]
    top = max(np.max(m[:, 2:], initial=0.0) for m in maps)
    if not top > 0:
        return None
    norm = LogNorm(vmin=top / 10**MAP_DECADES, vmax=top, clip=True)
    fig = _figure(figsize=(5.2 * len(dirs) + 1.2, 5.5))
    axes = fig.subplots(1, len(dirs), sharey=True, squeeze=False)[0]
    for ax, d, m in zip(axes, dirs, maps):
        mesh = ax.pcolormesh(
            freq, speed, m, norm=norm, cmap="viridis", shading="nearest", rasterized=True
        )
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        y = np.array([y0, y1])
        for k in HARMONICS:
            ax.plot(k * y, y, color="white", lw=0.8, alpha=0.4)
            ax.plot(ROLLER_RATIO * k * y, y, color="white", lw=0.8, alpha=0.3, ls="--")
            if k * y1 <= x1:
                ax.text(k * y1, y1, f"{k}×", fontsize="small", ha="center", va="bottom")
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_title(f"{sensor} {d}", pad=14)
        ax.set_xlabel("frequency [Hz]")
    axes[0].set_ylabel("speed [Hz]")
    fig.colorbar(mesh, ax=list(axes), label="runout amplitude [µm]")
    what = f"spectral map (lines k·speed, dashed {ROLLER_RATIO:g}·k·speed)"
    fig.suptitle(_sweep_title(study, what, sweep))
    return fig


def harmonics(sweep: rp.Sweep, sensor: str, study: str) -> Figure | None:
    """The amplitude [µm] of each of the sweep's orders over speed [Hz] at ``sensor``, log
    scale, one panel per direction (non-integer orders dashed); None when the sweep has no lines
    of that sensor."""
    dirs = _panels(sweep["lines"], sensor)
    if not dirs:
        return None
    fig = _figure(figsize=(5.2 * len(dirs) + 0.8, 5))
    axes = fig.subplots(1, len(dirs), sharey=True, squeeze=False)[0]
    for ax, d in zip(axes, dirs):
        amp = sweep["lines"][f"{sensor}/{d}"]
        for k, order in enumerate(sweep["orders"]):
            style = "-" if float(order).is_integer() else "--"
            ax.plot(sweep["speed_hz"], amp[:, k], style, marker=".", label=f"{order:g}×")
        ax.set_yscale("log", nonpositive="mask")
        ax.set_title(f"{sensor} {d}")
        ax.set_xlabel("speed [Hz]")
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel("line amplitude [µm]")
    axes[-1].legend(title="order", fontsize="small")
    fig.suptitle(_sweep_title(study, "amplitude of the orders over speed", sweep))
    return fig


def trial_mass(
    table: pd.DataFrame, names: pd.Series, direction: str, study: str
) -> Figure | None:
    """The 1× amplitude change and vector change [µm] against the baseline over speed [Hz], one
    panel per sensor in ``direction``, one colour per trial setting (``names``: text per job_id);
    None when the table has no channel in that direction."""
    t = table[table["channel"].str.endswith("/" + direction)]
    if t.empty:
        return None
    t = t.assign(curve=names.loc[t["job_id"]].to_numpy())
    sensors = list(dict.fromkeys(t["channel"].str.split("/").str[0]))
    fig = _figure(figsize=(7.5, 2.4 * len(sensors) + 1))
    axes = fig.subplots(len(sensors), 1, sharex=True, squeeze=False)[:, 0]
    for ax, sensor in zip(axes, sensors):
        rows = t[t["channel"] == f"{sensor}/{direction}"]
        for i, (curve, r) in enumerate(rows.groupby("curve", sort=False)):
            r = r.sort_values("speed_hz")
            speed, colour = r["speed_hz"], f"C{i}"
            ax.plot(speed, r["amplitude_change_um"], "-o", color=colour, label=f"{curve}: |A| − |A₀|")
            ax.plot(speed, r["vector_change_um"], "--s", color=colour, label=f"{curve}: |A − A₀|")
        ax.axhline(0.0, color="black", lw=0.6)
        ax.set_ylabel(f"{sensor} 1× change [µm]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize="small")
    axes[-1].set_xlabel("speed [Hz]")
    fig.suptitle(f"{study}: 1× response to the trial masses against the baseline ({direction})")
    return fig


def work_precision(summary: pd.DataFrame, reference: pd.Series, study: str) -> Figure:
    """Runout error against the reference (error_max_um) over CPU time, log–log: one colour and
    marker per integrator, every job a marker; per integrator and reference run (``reference``:
    reference_id per job_id, one per distinct physics) a line through its work-precision front
    (the jobs more accurate than every cheaper one). The legend counts the jobs shown and the
    failed."""
    summary = summary.assign(reference=reference.loc[summary["job_id"]].to_numpy())
    fig = _figure(figsize=(7, 5))
    ax = fig.subplots()
    for i, (integrator, jobs) in enumerate(summary.groupby("integrator", sort=False)):
        shown = jobs[(jobs["status"] == "ok") & (jobs["error_max_um"] > 0)]
        failed = int((jobs["status"] != "ok").sum())
        note = f"{len(shown)} of {len(jobs)} jobs" + (f", {failed} failed" if failed else "")
        style = {"color": f"C{i}", "marker": MARKERS[i % len(MARKERS)]}
        ax.plot([], [], label=f"{integrator} ({note})", **style)
        for _, run in shown.groupby("reference", sort=False):
            run = run.sort_values(["cpu_time_s", "error_max_um"])
            ax.plot(run["cpu_time_s"], run["error_max_um"], ls="none", **style)
            front = run[run["error_max_um"] < run["error_max_um"].cummin().shift(fill_value=np.inf)]
            ax.plot(front["cpu_time_s"], front["error_max_um"], lw=0.8, color=style["color"])
    ax.set_xscale("log")
    ax.set_yscale("log")
    # Over less than a decade the minor ticks are labelled too; tilted, they do not overlap.
    ax.tick_params(axis="x", which="minor", labelrotation=40, labelsize="x-small")
    ax.set_xlabel("CPU time [s]")
    ax.set_ylabel("runout error against the reference, max [µm]")
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    ax.set_title(f"{study}: work-precision")
    return fig


def _status_legend(ax: Axes, statuses: pd.Series) -> None:
    """A legend of the status colours that ``statuses`` uses."""
    handles = [
        Patch(color=STATUS_COLOURS.get(s, "lightgrey"), label=s) for s in dict.fromkeys(statuses)
    ]
    ax.legend(handles=handles, title="status", fontsize="small")


def timing(summary: pd.DataFrame, names: pd.Series, study: str) -> Figure:
    """CPU time [s] per job as bars coloured by status, tick labels ``names`` (text per job; the
    job id where empty), each bar annotated with Newton iterations per step ("–" for none)."""
    ticks = [n or j for n, j in zip(names.loc[summary["job_id"]], summary["job_id"])]
    fig = _figure(figsize=(max(6.5, 0.9 * len(summary) + 2), 5.5))
    ax = fig.subplots()
    x = np.arange(len(summary))
    cpu = summary["cpu_time_s"].to_numpy(dtype=float)
    bars = ax.bar(x, cpu, color=[STATUS_COLOURS.get(s, "lightgrey") for s in summary["status"]])
    per_step = summary["iterations_per_step"].to_numpy(dtype=float)
    notes = [f"{v:.2f}" if np.isfinite(v) else "–" for v in per_step]
    ax.bar_label(bars, notes, fontsize="small")
    ax.set_xticks(x, ticks, rotation=30, ha="right", fontsize="small")
    ax.set_ylabel("CPU time [s]")
    ax.margins(y=0.12)
    _status_legend(ax, summary["status"])
    ax.set_title(f"{study}: CPU time per job\n(on the bars: Newton iterations per step)")
    return fig


def stability(summary: pd.DataFrame, names: pd.Series, study: str) -> Figure:
    """A matrix integrator (rows) × setting (columns, ``names``: text per job of the other
    varying keys) coloured by status, each cell with error_max_um [µm] and cpu_time_s [s]."""
    df = summary.assign(setting=names.loc[summary["job_id"]].to_numpy())
    rows = list(dict.fromkeys(df["integrator"]))
    cols = list(dict.fromkeys(df["setting"]))
    rgb = np.ones((len(rows), len(cols), 3))
    fig = _figure(figsize=(max(5.0, 1.5 * len(cols) + 2.5), 1.1 * len(rows) + 2.8))
    ax = fig.subplots()
    for _, job in df.iterrows():
        r, c = rows.index(job["integrator"]), cols.index(job["setting"])
        rgb[r, c] = to_rgb(STATUS_COLOURS.get(job["status"], "lightgrey"))
        error = f"{job['error_max_um']:.3g} µm" if np.isfinite(job["error_max_um"]) else "–"
        cell = f"{error}\n{job['cpu_time_s']:.3g} s"
        ax.text(c, r, cell, ha="center", va="center", fontsize="small")
    ax.imshow(rgb, aspect="auto")
    ax.set_xticks(range(len(cols)), cols, rotation=30, ha="right", fontsize="small")
    ax.set_yticks(range(len(rows)), rows)
    _status_legend(ax, df["status"])
    ax.set_title(f"{study}: status, error max and CPU time")
    return fig


def campbell(path: PathLike, names: pd.Series, study: str) -> Figure | None:
    """The Campbell diagram of each ``/linear/<id>`` group (at most :data:`MAX_CAMPBELL_PANELS`,
    in the order of their first job), titled by that job's setting ``names``; None without
    any."""
    attrs = rp.job_attrs(path)
    if "linear_id" not in attrs:
        return None
    first = attrs.reset_index().drop_duplicates("linear_id").head(MAX_CAMPBELL_PANELS)
    systems = []
    with h5py.File(path, "r") as f:
        for _, job in first.iterrows():
            g = f.get(f"linear/{job['linear_id']}")
            if g is None or "campbell" not in g:
                continue
            crit = g["critical_speeds_hz"][()] if "critical_speeds_hz" in g else np.array([])
            title = names.get(job["job_id"], job["linear_id"]) if len(first) > 1 else ""
            systems.append((g["campbell/speed_hz"][()], g["campbell/whirl_hz"][()], crit, title))
    if not systems:
        return None
    fig = _figure(figsize=(5.2 * len(systems) + 0.8, 5))
    axes = fig.subplots(1, len(systems), sharey=True, squeeze=False)[0]
    for ax, (speed, whirl, crit, title) in zip(axes, systems):
        top = float(speed[-1])
        ax.plot(speed, whirl, color="tab:blue", lw=1)
        for k in HARMONICS:
            ax.plot(speed, k * speed, color="0.4", lw=0.8, ls="-" if k == 1 else ":")
            ax.annotate(f"{k}×", (top / k, top), fontsize="small", ha="center", va="bottom")
        ax.plot(crit, crit, "o", color="tab:red", label="critical speeds")
        for i, c in enumerate(crit):
            # Alternate below and above the point: neighbouring criticals lie close together.
            ax.annotate(f"{c:.2f} Hz", (c, c), xytext=(6, -12 if i % 2 == 0 else 4),
                        textcoords="offset points", fontsize="small", color="tab:red")
        ax.set_xlim(0, top)
        ax.set_ylim(0, top)
        ax.set_xlabel("spin speed [Hz]")
        ax.set_title(title, fontsize="small", pad=14)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("whirl frequency, stationary frame [Hz]")
    axes[0].legend(loc="lower right", fontsize="small")
    fig.suptitle(f"{study}: Campbell diagram on the linearised supports")
    return fig


def render(path: PathLike, outdir: PathLike, channel: str = "centre/vertical") -> list[Path]:
    """Writes the plots the results file ``path`` has data for into ``outdir`` (created if
    needed) and returns their paths, in the order of the module doc. ``channel`` is
    "SENSOR/DIR". Raises :class:`PlotError` when ``path`` is not a study results file or has no
    such channel."""
    check_results_file(path)
    sensor, _, direction = channel.partition("/")
    if direction not in DIRECTIONS:
        raise PlotError(f"channel {channel!r}: expected SENSOR/DIR, DIR {' or '.join(DIRECTIONS)}")
    summary = rp.load_summary(path)
    varying = rp.varying_keys(path)
    labels = rp.job_labels(path)
    study = str(rp.file_attrs(path).get("study_name", Path(path).stem))
    sweeps = rp.sweeps(path)
    trial = rp.analysis_table(path, "trial_mass")
    have = sorted({c for s in sweeps for c in s["lines"]} | set(trial.get("channel", [])))
    if have and channel not in have:
        raise PlotError(f"{path}: no channel {channel!r} (there are: {', '.join(have)})")
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    figures: list[tuple[str, Figure | None]] = []
    for s in sweeps:
        suffix = f"-{s['n']}" if len(sweeps) > 1 else ""
        figures.append((f"spectral_map{suffix}.png", spectral_map(s, sensor, study)))
        figures.append((f"harmonics{suffix}.png", harmonics(s, sensor, study)))
    if not trial.empty:
        names = settings(summary, labels, [k for k in varying if k != "speed.hz"])
        figures.append(("trial_mass.png", trial_mass(trial, names, direction, study)))
    if ((summary["status"] == "ok") & (summary["error_max_um"] > 0)).any():
        reference = rp.job_attrs(path)["reference_id"]
        figures.append(("work_precision.png", work_precision(summary, reference, study)))
    if 0 < len(summary) <= MAX_TIMING_JOBS:
        figures.append(("timing.png", timing(summary, settings(summary, labels, varying), study)))
    if "solver.integrator" in varying and len(varying) > 1:
        names = settings(summary, labels, [k for k in varying if k != "solver.integrator"])
        figures.append(("stability.png", stability(summary, names, study)))
    physics = [k for k in varying if k != "speed.hz" and not k.startswith("solver.")]
    figures.append(("campbell.png", campbell(path, settings(summary, labels, physics), study)))
    return [_save(fig, out / name) for name, fig in figures if fig is not None]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(
        description="PNG plots of a rotorsweep study results file (spectral maps, harmonics, "
        "trial-mass response, work-precision, timing, stability)."
    )
    p.add_argument("results", type=Path, help="results file of `rotorsweep run` or `merge`")
    p.add_argument(
        "-o", "--outdir", type=Path, help="folder for the PNGs (default: OUT-plots beside OUT.h5)"
    )
    p.add_argument(
        "--channel",
        default="centre/vertical",
        help="SENSOR/DIR: the sensor of the spectral maps and harmonics (both directions drawn) "
        "and the direction of the trial-mass panels (default: centre/vertical)",
    )
    a = p.parse_args(argv)
    outdir = a.outdir or a.results.with_name(a.results.stem + "-plots")
    try:
        written = render(a.results, outdir, a.channel)
    except PlotError as e:
        print(f"plots.py: error: {e}", file=sys.stderr)
        return 1
    for w in written:
        print(w)
    return 0


if __name__ == "__main__":
    sys.exit(main())
