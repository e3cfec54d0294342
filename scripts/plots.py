#!/usr/bin/env python3
"""PNG plots of a study's results file (``rotorsweep run STUDY -o OUT.h5``) or of a linear
analysis (``rotorsweep linear SCENE -o OUT.h5``).

    python3 scripts/plots.py OUT.h5 [-o DIR] [--channel centre/vertical]

Writes into DIR (default: ``OUT-plots`` beside the file), each plot only when the file holds its
data, and prints the paths written:

* ``spectral_map[-<n>].png``: per speed sweep with a map (``/analysis/sweeps/<n>``), the
  amplitude of the runout's fluctuating part (the mean, static sag, removed before the FFT)
  [µm, log colour scale] over frequency [Hz] × speed [Hz] up to the study's range (from its
  orders), one panel per direction of the chosen sensor, with the roll's lines f = k·speed
  (the study's integer orders k) and, dashed, the rollers' lines f = r·k·speed with r the
  scene's journal/roller diameter ratio (the jobs' ``roller_ratio:…`` attributes; none where
  the roller roundness follows the roll angle, r = 1);
* ``mean[-<n>].png``: per speed sweep, the mean runout (static sag and offset) [µm] over speed
  at each sensor, one panel per direction;
* ``harmonics[-<n>].png``: per speed sweep, the amplitude of each of the study's orders over
  speed (log), one panel per direction of the chosen sensor;
* ``trial_mass.png``: the 1× amplitude change |A| − |A₀| and vector change |A − A₀| against the
  baseline jobs over speed (``/analysis/trial_mass``), one panel per sensor in the chosen
  direction, one pair of curves per trial setting;
* ``work_precision.png``: runout error against the reference [µm] over CPU time [s], log–log,
  one panel per physics (the varying keys that are not ``solver.*`` nor ``reduction.*``, i.e.
  per reference run), one colour and marker per integrator, every point labelled with its
  solver setting, each integrator's work-precision front a line (jobs that ended ok; the
  legend counts the failed ones);
* ``timing.png``: CPU time [s] per job coloured by status, annotated with Newton iterations
  per step; vertical bars up to 12 jobs, one horizontal bar a job above (every job shown);
* ``stability.png``: when ``solver.integrator`` and other keys vary, a matrix integrator ×
  setting coloured by error class (:func:`error_class`: the decade of the max error, or the
  status of a job that did not end ok), with the status, error [µm] and CPU time [s] in the
  cells;
* ``campbell.png``: the Campbell diagram of each linearised system (``/linear/<id>``, at most
  four panels): damped whirl frequencies [Hz] of the model on its linearised supports over spin
  speed [Hz], one line per branch, each branch in range labelled at its right end with its
  plane at standstill (vertical / horizontal, from the first bending frequencies) and its whirl
  at the top speed (forward / backward), with the lines f = k·speed (k = 1…4, 1× solid) and the
  critical speeds; where the file has the log decrements every mode a marker by whirl
  (▲ forward, ▼ backward, ● mixed) coloured by its log decrement, with a colour bar.

Per linear system, each when its group holds the data (``rotorsweep linear -o`` writes them, a
study's ``/linear`` groups where its ``[linear]`` table asks), suffixed ``-<system>`` when
several systems have one:

* ``mode_shapes.png``: the lowest four lateral modes at the lowest and the highest speed,
  horizontal and vertical translation along the rotor (``linear -o --shapes``);
* ``bode.png`` and ``polar.png``: the 1× unbalance response per sensor, amplitude [µm] and
  phase [°] over speed (critical speeds dotted), and amplitude at angle φ;
* ``critical_map.png``: undamped critical speeds against the support stiffness, the actual
  supports' stiffness marked;
* ``floquet.png``: −ln max|μ| per revolution over speed (< 0 unstable), the Floquet-unstable
  ranges shaded, the damped modes' stability threshold dashed.

Per ramp job (a job whose speed changed while recording: its ``/jobs/<id>/waterfall``), suffixed
``-<job_id>`` when several jobs have one, titled by the job's setting:

* ``waterfall.png``: the amplitude [µm, log colour scale] of the Hanning spectra of
  half-overlapping time blocks (``/jobs/<id>/waterfall``) over frequency [Hz], a row per block
  at its mid time [s] with the block's mean speed [Hz] on the right axis (a hold or a
  coast-down reads as well as a run-up), one panel per direction of the chosen sensor, with the
  tracked orders' lines f = k·speed(t);
* ``order_map.png``: the tracked amplitude [µm, log] of each order (``/analysis/orders``) over
  the blocks' mean speed [Hz], one line per order, one panel per direction;
* ``order_bode.png``: the tracked 1× amplitude [µm, log] and phase [°] over speed per sensor,
  vertical and horizontal; where the file has the job's ``/linear/<linear_id>`` system with an
  unbalance response (a study's ``[linear] unbalance_response = true``) that steady-state
  response dashed over it, each tracked phase moved by whole turns nearest it, and the critical
  speeds dotted.

With ``--balance JSON`` (the output of ``rotorsweep balance OUT.h5 --json [--check]``):

* ``balancing.png``: the 1× amplitude [µm, log] per sensor and direction, one panel per speed,
  as bars: the reference run (before), the influence coefficients' prediction after the
  corrections and, with ``--check``, the check run of the corrected roll with its reduction
  [%]; the corrections (plane z, mass, angle) in the title.

With ``--compare SIMULATED.h5`` (the results file is a measured record of ``rotorsweep
import``, the simulated one the model's run-up; one ramp job each, as ``rotorsweep report
MEASURED --compare SIMULATED``), only these two:

* ``compare_waterfall.png``: measured and simulated waterfalls side by side, a row per
  direction, over frequency and the blocks' mean speed, on one colour scale;
* ``compare_orders.png``: the tracked order amplitudes [µm, log] over speed, measured solid and
  simulated dashed, one colour per order, a panel per direction.

Besides study results files, a ``rotorsweep linear -o`` file is accepted: it gets the Campbell
diagram and the per-system figures; and a ``rotorsweep simulate -o`` file, laid out as a study
of one job (no sweeps: its timing bar, and its work-precision point when it has an error).

Numbers in labels are written as ``rotorsweep report`` writes them (:func:`number_text`).

The ``-<n>`` suffix (the sweep's number in the file) is added only when the file has several
sweeps. ``--channel SENSOR/DIR`` picks the sensor of the maps, harmonics, waterfalls and order
maps and the direction of the trial-mass panels (default centre/vertical; a ramp job without a
"centre" sensor then shows its first sensor). Importable: :func:`render` does the same and returns the paths. The
figures are drawn on Agg canvases of their own; matplotlib's global backend is left alone.
Exit code 1, with a message naming the file, when it is neither.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import LogNorm, Normalize, TwoSlopeNorm, to_rgb
from matplotlib.figure import Figure
from matplotlib.patches import Patch
from matplotlib.ticker import ScalarFormatter

import rotorsweep as rp
from rotorsweep import PathLike

#: The channel drawn when none is asked for (``--channel``).
DEFAULT_CHANNEL = "centre/vertical"
#: Resolution of the PNG files [dots per inch].
DPI = 110
#: Directions of the runout channels, in panel order.
DIRECTIONS = ("vertical", "horizontal")
#: Roll harmonics drawn on the Campbell diagrams (f = k · speed).
HARMONICS = (1, 2, 3, 4)
#: Prefix of the job attributes that give each roller's line ratio (src/study/post.rs).
ROLLER_RATIO = "roller_ratio:"
#: Decades of amplitude below the map's maximum that the colour scale spans.
MAP_DECADES = 4
#: Most linearised systems drawn in the Campbell diagram (one panel each).
MAX_CAMPBELL_PANELS = 4
#: Up to this many jobs the timing chart has vertical bars; above, one horizontal bar a job.
MAX_TIMING_JOBS = 12
#: Statuses of a run that reached its end time (its records are complete).
COMPLETED = ("ok", "untrusted")
#: Fill colour of each job status.
STATUS_COLOURS = {"ok": "#9ccc65", "untrusted": "#fff176", "diverged": "#ef5350", "budget": "#ffb74d"}
#: Fill colour of each error class of :func:`error_class` (src/report.rs: CLASS_COLOURS).
CLASS_COLOURS = {
    "< 1 µm": "#a5d6a7",
    "1–10 µm": "#fff59d",
    "10–100 µm": "#ffcc80",
    "≥ 100 µm": "#ef9a9a",
    "no reference": "#b3e5fc",
    "untrusted": "#80cbc4",
    "diverged": "#ce93d8",
    "budget": "#bdbdbd",
}
MARKERS = "osD^v<>"
#: Most physics panels of the work-precision figure (more: one panel, a marker per physics).
MAX_WORK_PANELS = 9


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


def check_results_file(path: PathLike) -> bool:
    """Raises :class:`PlotError` naming ``path`` unless it is an HDF5 file written by
    ``rotorsweep run`` or ``merge`` (tool attribute "rotorsweep" and a ``/summary`` table) or by
    ``rotorsweep linear -o`` (a ``/linear`` group); True for a study results file."""
    if not Path(path).is_file():
        raise PlotError(f"{path}: no such file")
    try:
        with h5py.File(path, "r") as f:
            tool = f.attrs.get("tool")
            has_summary = "summary" in f
            has_linear = "linear" in f
    except OSError as e:
        raise PlotError(f"{path}: not an HDF5 file ({e})") from None
    if tool != "rotorsweep" or not (has_summary or has_linear):
        raise PlotError(
            f"{path}: not a rotorsweep study results file (no /summary table; "
            "`rotorsweep run STUDY -o OUT.h5` writes one) nor a `rotorsweep linear -o` file "
            "(no /linear group)"
        )
    return has_summary


def number_text(x: float) -> str:
    """A number as ``rotorsweep report`` writes it (src/report.rs ``number_text``): shortest
    round-trip digits, scientific below 1e-3 and from 1e6 (``1e-4``, not ``0.0001``), no
    trailing ``.0``."""
    if not np.isfinite(x):
        return "–"
    if x != 0 and (abs(x) < 1e-3 or abs(x) >= 1e6):
        return np.format_float_scientific(x, unique=True, trim="-", exp_digits=1).replace("+", "")
    text = repr(float(x))
    return text[:-2] if text.endswith(".0") else text


def error_class(status: str, error_max_um: float) -> str:
    """The class of a job's outcome (src/report.rs ``error_class``): its status when it did not
    end ok, "no reference" without an error, else the decade of its max runout error."""
    if status != "ok":
        return status
    if not np.isfinite(error_max_um):
        return "no reference"
    for bound, name in ((1.0, "< 1 µm"), (10.0, "1–10 µm"), (100.0, "10–100 µm")):
        if error_max_um < bound:
            return name
    return "≥ 100 µm"


def _format(value: object) -> str:
    return number_text(value) if isinstance(value, float) else str(value)


def settings(summary: pd.DataFrame, labels: pd.DataFrame, keys: list[str]) -> pd.Series:
    """A short text per job (index job_id, summary order) naming its values of the varying
    ``keys``: the label of each labelled axis among them (``labels`` as
    :func:`rotorsweep.job_labels` returns it), then ``key=value`` for every key that no shown
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


def spectral_map(
    sweep: rp.Sweep,
    sensor: str,
    study: str,
    ratios: list[float] | None = None,
    mean_removed: bool = True,
) -> Figure | None:
    """The sweep's spectral map of ``sensor`` (amplitude [µm] of the fluctuating part over
    frequency [Hz] × speed [Hz], the stored range), one panel per direction on a shared log
    colour scale that spans :data:`MAP_DECADES` below the largest amplitude; white lines at the
    sweep's integer orders k·speed and, dashed, at r·k·speed for each roller ratio r in
    ``ratios`` (:func:`roller_ratios`; None: not known, no roller lines said). A file written before the mean was removed
    (``mean_removed`` False) has it in the 0 Hz bin and the next one: those two are left out of
    the colour scale (clipped to its top). None when the sweep has no map of that sensor or it
    is zero."""
    dirs = _panels(sweep["maps"], sensor)
    if not dirs or sweep["freq_hz"] is None:
        return None
    maps = [sweep["maps"][f"{sensor}/{d}"] for d in dirs]
    freq, speed = sweep["freq_hz"], sweep["speed_hz"]
    skip = 0 if mean_removed else 2
    top = max(np.max(m[:, skip:], initial=0.0) for m in maps)
    if not top > 0:
        return None
    orders = [int(o) for o in sweep["orders"] if float(o).is_integer() and o > 0]
    known = ratios is not None
    ratios = [r for r in (ratios or []) if abs(r - 1.0) > 1e-9]
    norm = LogNorm(vmin=top / 10**MAP_DECADES, vmax=top, clip=True)
    fig = _figure(figsize=(5.2 * len(dirs) + 1.2, 5.8))
    axes = fig.subplots(1, len(dirs), sharey=True, squeeze=False)[0]
    for ax, d, m in zip(axes, dirs, maps):
        mesh = ax.pcolormesh(
            freq, speed, m, norm=norm, cmap="viridis", shading="nearest", rasterized=True
        )
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        y = np.array([y0, y1])
        for k in orders:
            ax.plot(k * y, y, color="white", lw=0.8, alpha=0.45)
            if k * y1 <= x1:
                ax.text(k * y1, y1, f"{k}×", fontsize="small", ha="center", va="bottom")
            for r in ratios:
                ax.plot(r * k * y, y, color="white", lw=0.8, alpha=0.35, ls="--")
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_title(f"{sensor} {d}", pad=14)
        ax.set_xlabel("frequency [Hz]")
    axes[0].set_ylabel("speed [Hz]")
    fig.colorbar(mesh, ax=list(axes), label="runout amplitude, mean removed [µm]")
    if ratios:
        rollers = ", ".join(number_text(round(r, 4)) for r in ratios)
        what = f"spectral map (solid k·speed; dashed rollers' lines {rollers}·k·speed)"
    elif known:
        what = "spectral map (lines k·speed; the rollers' lines lie on them)"
    else:
        what = "spectral map (lines k·speed)"
    fig.suptitle(_sweep_title(study, what, sweep))
    return fig


def roller_ratios(attrs: pd.DataFrame, job_ids: list[str]) -> list[float] | None:
    """The distinct roller line ratios (``roller_ratio:<node>/<roller>`` attributes, ascending)
    of the jobs ``job_ids`` (``attrs`` as :func:`rotorsweep.job_attrs` gives them); None in a
    file written before they were stored (unknown), [] for a scene without rollers."""
    cols = [c for c in attrs.columns if str(c).startswith(ROLLER_RATIO)]
    if not cols:
        return None
    values = attrs.loc[[j for j in job_ids if j in attrs.index], cols].to_numpy(dtype=float)
    values = values[np.isfinite(values)]
    return sorted({round(float(v), 9) for v in values})


def sweep_means(path: PathLike, n: int) -> dict[str, np.ndarray]:
    """The mean runout [µm] over speed of sweep ``n`` by channel (``/analysis/sweeps/<n>/mean``);
    {} in a file written before the mean was stored apart."""
    with h5py.File(path, "r") as f:
        g = f.get(f"analysis/sweeps/{n}/mean")
        if g is None:
            return {}
        out: dict[str, np.ndarray] = {}
        g.visititems(lambda name, obj: out.__setitem__(name, obj[()])
                     if isinstance(obj, h5py.Dataset) else None)
        return out


def mean_runout(sweep: rp.Sweep, means: dict[str, np.ndarray], study: str) -> Figure | None:
    """The mean runout (static sag and offset) [µm] over speed [Hz], one panel per direction,
    one line per sensor; None without stored means."""
    dirs = [d for d in DIRECTIONS if any(c.endswith("/" + d) for c in means)]
    if not dirs:
        return None
    fig = _figure(figsize=(5.0 * len(dirs) + 0.8, 4.2))
    axes = fig.subplots(1, len(dirs), sharey=True, squeeze=False)[0]
    for ax, d in zip(axes, dirs):
        for c in sorted(c for c in means if c.endswith("/" + d)):
            ax.plot(sweep["speed_hz"], means[c], marker=".", label=c.split("/")[0])
        ax.set_title(d)
        ax.set_xlabel("speed [Hz]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("mean runout [µm]")
    axes[-1].legend(title="sensor", fontsize="small")
    fig.suptitle(_sweep_title(study, "mean runout over speed (removed before the spectra)", sweep))
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
    axes[-1].legend(title="order", fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
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


def work_precision(
    summary: pd.DataFrame,
    reference: pd.Series,
    study: str,
    solver: pd.Series | None = None,
    physics: pd.Series | None = None,
    physics_id: pd.Series | None = None,
) -> Figure:
    """Runout error against the reference (error_max_um) over CPU time, log–log: one panel per
    physics (``physics_id``: a value per job_id that is the same for the same physics, by
    default ``physics``; at most :data:`MAX_WORK_PANELS`, else one panel), titled with its jobs'
    ``physics`` (text per job_id of the keys that change the physics, several joined by " / "),
    one colour and marker per integrator, every job a marker labelled with its solver setting
    (``solver``: text per job_id); per integrator and reference run (``reference``:
    reference_id per job_id) a line through its work-precision front (the jobs more accurate
    than every cheaper one). The legend counts the jobs shown and the failed."""
    ids = summary["job_id"]
    empty = pd.Series("", index=ids.to_numpy())
    solver = empty if solver is None else solver
    physics = empty if physics is None else physics
    physics_id = physics if physics_id is None else physics_id
    summary = summary.assign(
        reference=reference.loc[ids].to_numpy(),
        solver_setting=solver.loc[ids].to_numpy(),
        physics=physics.loc[ids].to_numpy(),
        physics_id=physics_id.loc[ids].to_numpy(),
    )
    groups = list(dict.fromkeys(summary["physics_id"]))
    if len(groups) > MAX_WORK_PANELS:
        groups = [None]
    # One panel wide, so that its labels have room; several at 6 inches each, 3 a row.
    width, height = (8.5, 6.2) if len(groups) == 1 else (6.0, 5.0)
    fig = _figure(figsize=(width * min(len(groups), 3) + 0.5,
                           height * ((len(groups) + 2) // 3) + 0.4))
    axes = fig.subplots((len(groups) + 2) // 3, min(len(groups), 3), squeeze=False).ravel()
    integrators = list(dict.fromkeys(summary["integrator"]))
    for ax, group in zip(axes, groups):
        jobs_here = summary if group is None else summary[summary["physics_id"] == group]
        title = " / ".join(p for p in dict.fromkeys(jobs_here["physics"]) if p)
        if group is not None and title:
            ax.set_title(title, fontsize="medium")
        drawn = jobs_here["status"].isin(COMPLETED) & (jobs_here["error_max_um"] > 0)
        if not drawn.any():
            failed = ", ".join(f"{i}: {s}" for i, s in zip(jobs_here["integrator"],
                                                           jobs_here["status"]))
            ax.text(0.5, 0.5, f"no job with an error to draw\n({failed})", ha="center",
                    va="center", transform=ax.transAxes, fontsize="small")
            ax.set_xticks([])
            ax.set_yticks([])
            continue
        for integrator, jobs in jobs_here.groupby("integrator", sort=False):
            i = integrators.index(integrator)
            shown = jobs[jobs["status"].isin(COMPLETED) & (jobs["error_max_um"] > 0)]
            failed = int((~jobs["status"].isin(COMPLETED)).sum())
            untrusted = int((jobs["status"] == "untrusted").sum())
            note = (f"{len(shown)} of {len(jobs)} jobs"
                    + (f", {untrusted} untrusted" if untrusted else "")
                    + (f", {failed} failed" if failed else ""))
            style = {"color": f"C{i}", "marker": MARKERS[i % len(MARKERS)]}
            ax.plot([], [], label=f"{integrator} ({note})", **style)
            for _, run in shown.groupby("reference", sort=False):
                run = run.sort_values(["cpu_time_s", "error_max_um"])
                ax.plot(run["cpu_time_s"], run["error_max_um"], ls="none", **style)
                best = run["error_max_um"].cummin().shift(fill_value=np.inf)
                front = run[run["error_max_um"] < best]
                ax.plot(front["cpu_time_s"], front["error_max_um"], lw=0.8, color=style["color"])
            for _, job in shown.iterrows():
                if job["solver_setting"]:
                    ax.annotate(job["solver_setting"], (job["cpu_time_s"], job["error_max_um"]),
                                xytext=(4, 3), textcoords="offset points", fontsize="xx-small",
                                color=style["color"])
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.margins(x=0.25, y=0.15)
        # Over less than a decade the minor ticks are labelled too; tilted, they do not overlap.
        ax.tick_params(axis="x", which="minor", labelrotation=40, labelsize="x-small")
        ax.set_xlabel("CPU time [s]")
        ax.set_ylabel("runout error against the reference, max [µm]")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize="small")
    for ax in axes[len(groups):]:
        ax.set_visible(False)
    what = "work-precision" + (" per physics" if len(groups) > 1 else "")
    fig.suptitle(f"{study}: {what} (labels: solver setting)")
    return fig


def _status_legend(ax: Axes, statuses: pd.Series) -> None:
    """A legend of the status colours that ``statuses`` uses."""
    handles = [
        Patch(color=STATUS_COLOURS.get(s, "lightgrey"), label=s) for s in dict.fromkeys(statuses)
    ]
    ax.legend(handles=handles, title="status", fontsize="small")


def timing(summary: pd.DataFrame, names: pd.Series, study: str) -> Figure:
    """CPU time [s] per job as bars coloured by status, labelled ``names`` (text per job; the
    job id where empty), each bar annotated with Newton iterations per step ("–" for none):
    vertical bars up to :data:`MAX_TIMING_JOBS` jobs, horizontal ones (one row a job, in job
    order from the top) above, so that every job is shown whatever the study's size."""
    ticks = [n or j for n, j in zip(names.loc[summary["job_id"]], summary["job_id"])]
    cpu = summary["cpu_time_s"].to_numpy(dtype=float)
    per_step = summary["iterations_per_step"].to_numpy(dtype=float)
    notes = [f"{v:.2f}" if np.isfinite(v) else "–" for v in per_step]
    colours = [STATUS_COLOURS.get(s, "lightgrey") for s in summary["status"]]
    x = np.arange(len(summary))
    if len(summary) <= MAX_TIMING_JOBS:
        fig = _figure(figsize=(max(6.5, 0.9 * len(summary) + 2), 5.5))
        ax = fig.subplots()
        bars = ax.bar(x, cpu, color=colours)
        ax.set_xticks(x, ticks, rotation=30, ha="right", fontsize="small")
        ax.set_ylabel("CPU time [s]")
        ax.margins(y=0.12)
    else:
        longest = max((len(t) for t in ticks), default=10)
        fig = _figure(figsize=(7.5 + 0.06 * longest, 0.19 * len(summary) + 1.6))
        ax = fig.subplots()
        bars = ax.barh(x, cpu, color=colours, height=0.75)
        ax.set_yticks(x, ticks, fontsize=6)
        ax.set_ylim(len(summary) - 0.5, -0.5)
        ax.set_xlabel("CPU time [s]")
        ax.margins(x=0.12)
        ax.grid(alpha=0.3, axis="x")
    ax.bar_label(bars, notes, fontsize="x-small" if len(summary) > MAX_TIMING_JOBS else "small",
                 padding=2)
    _status_legend(ax, summary["status"])
    ax.set_title(f"{study}: CPU time per job, {len(summary)} jobs\n"
                 "(on the bars: Newton iterations per step)")
    return fig


def stability(summary: pd.DataFrame, names: pd.Series, study: str) -> Figure:
    """A matrix integrator (rows) × setting (columns, ``names``: text per job of the other
    varying keys) coloured by :func:`error_class` (green below 1 µm to red from 100 µm; failed
    jobs by status), each cell with the status when not ok, error_max_um [µm] and cpu_time_s
    [s]; several jobs in one cell take the worst class."""
    df = summary.assign(setting=names.loc[summary["job_id"]].to_numpy())
    rows = list(dict.fromkeys(df["integrator"]))
    cols = list(dict.fromkeys(df["setting"]))
    order = list(CLASS_COLOURS)
    worst: dict[tuple[int, int], str] = {}
    text: dict[tuple[int, int], list[str]] = {}
    for _, job in df.iterrows():
        r, c = rows.index(job["integrator"]), cols.index(job["setting"])
        cls = error_class(job["status"], float(job["error_max_um"]))
        if (r, c) not in worst or order.index(cls) > order.index(worst[(r, c)]):
            worst[(r, c)] = cls
        error = f"{job['error_max_um']:.3g} µm" if np.isfinite(job["error_max_um"]) else "–"
        head = "" if job["status"] == "ok" else f"{job['status']}\n"
        text.setdefault((r, c), []).append(f"{head}{error}\n{job['cpu_time_s']:.3g} s")
    rgb = np.ones((len(rows), len(cols), 3))
    for (r, c), cls in worst.items():
        rgb[r, c] = to_rgb(CLASS_COLOURS.get(cls, "lightgrey"))
    fig = _figure(figsize=(max(5.5, 1.5 * len(cols) + 3.5), 1.1 * len(rows) + 2.8))
    ax = fig.subplots()
    ax.imshow(rgb, aspect="auto")
    for (r, c), lines in text.items():
        ax.text(c, r, "\n".join(lines), ha="center", va="center", fontsize="small")
    ax.set_xticks(range(len(cols)), cols, rotation=30, ha="right", fontsize="small")
    ax.set_yticks(range(len(rows)), rows)
    used = [c for c in order if c in set(worst.values())]
    handles = [Patch(color=CLASS_COLOURS[c], label=c) for c in used]
    ax.legend(handles=handles, title="max error / status", fontsize="small",
              loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(f"{study}: error class, max error and CPU time per integrator and setting")
    return fig


#: Marker and legend text of each whirl code of ``campbell/whirl`` (1 forward, -1 backward,
#: 0 mixed).
WHIRL_MARKERS = {1: ("^", "forward"), -1: ("v", "backward"), 0: ("o", "mixed")}
#: Lowest lateral modes drawn in the mode-shape figure, at each of two speeds.
MAX_SHAPE_MODES = 4
#: Most sensors drawn in the Bode and polar figures (one column or polar axes each).
MAX_SENSORS = 4
#: Polar plots label speeds only where the amplitude is at least this share of the largest.
POLAR_LABEL_SHARE = 0.1
#: Lowest critical speeds drawn on the critical-speed map.
MAX_MAP_CRITICALS = 6


def linear_system(g: h5py.Group) -> dict[str, object]:
    """The datasets of one ``/linear/<name>`` group as arrays (text decoded), under their path in
    the group (``campbell/speed_hz``, ``critical_speeds_hz``, …), and its attributes
    ``stability_threshold_hz``, ``vertical_hz`` and ``horizontal_hz`` (None when absent)."""
    data: dict[str, object] = {}

    def visit(name: str, obj: h5py.HLObject) -> None:
        if isinstance(obj, h5py.Dataset):
            v = obj[()]
            data[name] = v.astype(str) if v.dtype.kind == "O" else v

    g.visititems(visit)
    for name in ("stability_threshold_hz", "vertical_hz", "horizontal_hz"):
        value = g.attrs.get(name)
        data[name] = None if value is None else float(value)
    return data


def _linear_systems(path: PathLike) -> dict[str, dict[str, object]]:
    """Every ``/linear/<name>`` group with Campbell data, by name."""
    with h5py.File(path, "r") as f:
        groups = f.get("linear", {})
        return {n: linear_system(groups[n]) for n in groups if "campbell" in groups[n]}


def _over_speed(sys_: dict[str, object]) -> bool:
    """Whether a system was solved at two or more speeds (a curve over speed to draw)."""
    return len(sys_["campbell/speed_hz"]) >= 2


def _log_dec_norm(values: np.ndarray) -> Normalize:
    """Colour scale of log decrements: red for the least damped, centred at zero (white-yellow)
    when some are negative (unstable)."""
    lo, hi = float(np.nanmin(values)), float(np.nanmax(values))
    hi = max(hi, abs(lo) * 1e-3, 1e-12)
    if lo < 0:
        return TwoSlopeNorm(vmin=lo, vcenter=0.0, vmax=hi)
    return Normalize(vmin=0.0, vmax=hi)


def _campbell_panel(ax: Axes, sys_: dict[str, object], title: str) -> object | None:
    """One Campbell panel; returns the scatter of the log decrements (None when not stored)."""
    speed = np.asarray(sys_["campbell/speed_hz"])
    whirl = np.asarray(sys_["campbell/whirl_hz"])
    top = float(speed[-1])
    branch = sys_.get("campbell/branch")
    if branch is not None:
        # One line per Campbell branch (followed by mode shape), not per rank.
        for b in np.unique(branch[branch >= 0]):
            rows, cols = np.nonzero(branch == b)
            order = np.argsort(rows)
            ax.plot(speed[rows[order]], whirl[rows[order], cols[order]], color="0.6", lw=0.8)
    else:
        ax.plot(speed, whirl, color="tab:blue", lw=1)
    scatter = None
    log_dec = sys_.get("campbell/log_dec")
    shown = whirl <= top
    if log_dec is not None and shown.any():
        norm = _log_dec_norm(np.asarray(log_dec)[shown])
        codes = np.asarray(sys_.get("campbell/whirl", np.zeros_like(whirl)))
        grid = np.broadcast_to(speed[:, None], whirl.shape)
        for code, (marker, label) in WHIRL_MARKERS.items():
            pick = shown & (np.rint(codes) == code)
            if pick.any():
                scatter = ax.scatter(
                    grid[pick], whirl[pick], c=log_dec[pick], norm=norm, cmap="RdYlGn",
                    marker=marker, s=18, edgecolors="0.3", linewidths=0.3, zorder=3,
                )
            ax.scatter([], [], marker=marker, color="0.4", label=f"{label} whirl")
    for k in HARMONICS:
        ax.plot(speed, k * speed, color="0.2" if k == 1 else "0.5", lw=1.2 if k == 1 else 0.8,
                ls="-" if k == 1 else ":")
        # Where the line leaves the top edge; 1× leaves at the corner, so its label goes inside.
        if k == 1:
            ax.annotate("1×", (top, top), xytext=(-4, -4), textcoords="offset points",
                        fontsize="small", ha="right", va="top")
        else:
            ax.annotate(f"{k}×", (top / k, top), fontsize="small", ha="center", va="bottom")
    _label_branches(ax, sys_, top)
    crit = np.asarray(sys_.get("critical_speeds_hz", []))
    ax.plot(crit, crit, "o", mfc="none", mec="tab:red", ms=9, mew=1.5, label="critical speeds",
            zorder=4)
    for i, c in enumerate(crit):
        # Alternate below and above the point: neighbouring criticals lie close together; in
        # the right part of the panel, left of the point, clear of the branch labels there.
        right = c > 0.6 * top
        ax.annotate(f"{c:.2f} Hz", (c, c), xytext=(-8 if right else 8, -12 if i % 2 == 0 else 4),
                    textcoords="offset points", fontsize="small", color="tab:red",
                    ha="right" if right else "left")
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_xlabel("spin speed [Hz]")
    ax.set_title(title, fontsize="small", pad=14)
    ax.grid(alpha=0.3)
    return scatter


def _branch_names(sys_: dict[str, object]) -> list[tuple[float, str]]:
    """Per Campbell branch in the diagram's range: (its frequency at the top speed [Hz], its
    label): the plane at the lowest speed (vertical / horizontal for the branch nearest, within
    2 %, to the system's first bending frequency in that plane, attributes ``vertical_hz`` and
    ``horizontal_hz``: each plane names one branch, so a near-degenerate pair gets one of each)
    and the whirl at the top speed (forward / backward / mixed). [] without stored branches."""
    speed = np.asarray(sys_["campbell/speed_hz"])
    whirl = np.asarray(sys_["campbell/whirl_hz"])
    branch = sys_.get("campbell/branch")
    codes = sys_.get("campbell/whirl")
    if branch is None:
        return []
    branch = np.asarray(branch)
    top = float(speed[-1])
    ends: dict[int, tuple[float, float, int, int]] = {}
    for b in np.unique(branch[branch >= 0]):
        rows, cols = np.nonzero(branch == b)
        order = np.argsort(rows)
        rows, cols = rows[order], cols[order]
        f0, f1 = whirl[rows[0], cols[0]], whirl[rows[-1], cols[-1]]
        if 0 < f1 <= top and rows[-1] == len(speed) - 1:
            ends[int(b)] = (float(f0), float(f1), int(rows[-1]), int(cols[-1]))
    planes: dict[int, str] = {}
    for attr, name in (("vertical_hz", "vertical"), ("horizontal_hz", "horizontal")):
        f = sys_.get(attr)
        free = [b for b in ends if b not in planes]
        if f is None or not np.isfinite(f) or not free:
            continue
        near = min(free, key=lambda b: abs(ends[b][0] - f))
        if abs(ends[near][0] - f) <= 0.02 * f:
            planes[near] = name
    out = []
    for b, (_, f1, r, c) in ends.items():
        parts = [planes[b]] if b in planes else []
        if codes is not None:
            parts.append(WHIRL_MARKERS[int(np.rint(np.asarray(codes)[r, c]))][1])
        if parts:
            out.append((f1, ", ".join(parts)))
    return sorted(out)


def _label_branches(ax: Axes, sys_: dict[str, object], top: float) -> None:
    """Each branch's label (:func:`_branch_names`) at its right end, inside the axes; labels of
    neighbouring branches alternate above and below their lines."""
    for i, (f, name) in enumerate(_branch_names(sys_)):
        ax.annotate(name, (top, f), xytext=(-4, 3 if i % 2 else -3), textcoords="offset points",
                    ha="right", va="bottom" if i % 2 else "top", fontsize="x-small",
                    color="0.25")


def campbell(systems: list[tuple[str, dict[str, object]]], study: str) -> Figure | None:
    """The Campbell diagram of each linear system (``(title, data)``; at most
    :data:`MAX_CAMPBELL_PANELS` panels): damped whirl frequencies [Hz] over spin speed [Hz], a
    grey line per branch (per rank when the branches are not stored), the 1× line (solid) and
    2×–4× (dotted), the critical speeds; where the log decrements are stored (``rotorsweep
    linear -o``) each mode a marker by whirl (▲ forward, ▼ backward, ● mixed) coloured by its log
    decrement, with a colour bar. None without any system of two or more speeds."""
    systems = [s for s in systems if _over_speed(s[1])][:MAX_CAMPBELL_PANELS]
    if not systems:
        return None
    fig = _figure(figsize=(5.2 * len(systems) + 1.6, 5.4))
    axes = fig.subplots(1, len(systems), sharey=True, squeeze=False)[0]
    scatters = [_campbell_panel(ax, data, title) for ax, (title, data) in zip(axes, systems)]
    axes[0].set_ylabel("damped whirl frequency, stationary frame [Hz]")
    axes[0].legend(loc="lower right", fontsize="small")
    shown = [s for s in scatters if s is not None]
    if shown:
        fig.colorbar(shown[0], ax=list(axes), label="log decrement δ (< 0: unstable)")
    fig.suptitle(f"{study}: Campbell diagram on the linearised supports")
    return fig


def _study_systems(path: PathLike, names: pd.Series) -> list[tuple[str, dict[str, object]]]:
    """The linear systems of a study in the order of their first job, titled by that job's
    setting ``names`` (no title for a single one)."""
    attrs = rp.job_attrs(path)
    if "linear_id" not in attrs:
        return []
    first = attrs.reset_index().drop_duplicates("linear_id")
    systems = _linear_systems(path)
    first = first[first["linear_id"].isin(systems)]
    return [
        (names.get(job["job_id"], job["linear_id"]) if len(first) > 1 else "",
         systems[job["linear_id"]])
        for _, job in first.iterrows()
    ]


def _mark_criticals(ax: Axes, sys_: dict[str, object]) -> None:
    for c in np.asarray(sys_.get("critical_speeds_hz", [])):
        ax.axvline(c, color="tab:red", lw=0.8, ls=":")


def mode_shapes(sys_: dict[str, object], title: str) -> Figure | None:
    """The lowest :data:`MAX_SHAPE_MODES` lateral modes at the lowest and the highest stored
    speed: horizontal (x) and vertical (y) translation along the rotor, real part (the shape at
    phase 0, largest translation 1) and the envelope ±|X|; None without stored shapes
    (``rotorsweep linear -o --shapes``)."""
    if "shapes/x_re" not in sys_:
        return None
    z = np.asarray(sys_["shapes/node_z_mm"])
    parts = {p: np.asarray(sys_[f"shapes/{p}"]) for p in ("x_re", "x_im", "y_re", "y_im")}
    speed = np.asarray(sys_["campbell/speed_hz"])
    freq, log_dec = np.asarray(sys_["campbell/whirl_hz"]), sys_.get("campbell/log_dec")
    codes = sys_.get("campbell/whirl")
    n = min(MAX_SHAPE_MODES, parts["x_re"].shape[1])
    rows = [0] if len(speed) == 1 else [0, len(speed) - 1]
    fig = _figure(figsize=(3.4 * n + 0.5, 2.9 * len(rows) + 1.0))
    axes = fig.subplots(len(rows), n, sharex=True, sharey=True, squeeze=False)
    for r, s in enumerate(rows):
        for k in range(n):
            ax = axes[r, k]
            for d, colour, name in (("x", "tab:blue", "horizontal x"), ("y", "tab:orange",
                                                                       "vertical y")):
                re, im = parts[f"{d}_re"][s, k], parts[f"{d}_im"][s, k]
                size = np.hypot(re, im)
                ax.plot(z, re, color=colour, lw=1.5, marker=".", label=f"{name}, real part")
                ax.fill_between(z, -size, size, color=colour, alpha=0.12, lw=0)
            ax.axhline(0.0, color="black", lw=0.5)
            note = f"{freq[s, k]:.2f} Hz"
            if log_dec is not None:
                note += f", δ {log_dec[s, k]:.3g}"
            if codes is not None:
                note += f", {WHIRL_MARKERS[int(np.rint(codes[s, k]))][1]}"
            ax.set_title(f"mode {k + 1} at {speed[s]:g} Hz\n{note}", fontsize="small")
            ax.grid(alpha=0.3)
        axes[r, 0].set_ylabel("translation (largest 1)")
    for ax in axes[-1]:
        ax.set_xlabel("z [mm]")
    axes[0, 0].legend(fontsize="x-small", loc="lower center")
    fig.suptitle(f"{title}: lateral mode shapes (shaded: envelope ±|X| of the orbit)")
    return fig


def _responses(sys_: dict[str, object]) -> list[str]:
    """The sensors with an unbalance response, at most :data:`MAX_SENSORS`."""
    names = [k.split("/")[1] for k in sys_ if k.startswith("unbalance_response/")
             and k.endswith("/vertical/amplitude_um")]
    return names[:MAX_SENSORS]


def bode(sys_: dict[str, object], title: str) -> Figure | None:
    """Bode plot of the 1× unbalance response per sensor (one column each): amplitude [µm] and
    phase [°] (unwrapped, against roll angle 0; none at zero amplitude) over spin speed [Hz],
    vertical and horizontal, the critical speeds dotted; None without a stored response."""
    sensors = _responses(sys_)
    if not sensors or not _over_speed(sys_):
        return None
    speed = np.asarray(sys_["campbell/speed_hz"])
    fig = _figure(figsize=(4.6 * len(sensors) + 0.6, 6.2))
    axes = fig.subplots(2, len(sensors), sharex=True, squeeze=False)
    for c, sensor in enumerate(sensors):
        for d, colour in zip(DIRECTIONS, ("tab:orange", "tab:blue")):
            key = f"unbalance_response/{sensor}/{d}"
            amp = np.asarray(sys_[f"{key}/amplitude_um"])
            # Without amplitude (at standstill) the phase means nothing: left out, and the rest
            # unwrapped.
            phase = _unwrap_deg(np.where(amp > 0, np.asarray(sys_[f"{key}/phase_deg"]), np.nan))
            axes[0, c].plot(speed, amp, color=colour, label=d)
            axes[1, c].plot(speed, phase, color=colour, label=d)
        axes[0, c].set_title(sensor)
        axes[1, c].set_xlabel("spin speed [Hz]")
        for ax in axes[:, c]:
            _mark_criticals(ax, sys_)
            ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel("1× amplitude [µm]")
    axes[1, 0].set_ylabel("1× phase [°] (x = A cos(θ + φ))")
    axes[0, 0].plot([], [], color="tab:red", lw=0.8, ls=":", label="critical speeds")
    axes[0, 0].legend(fontsize="small")
    fig.suptitle(f"{title}: unbalance response (Bode)")
    return fig


def polar(sys_: dict[str, object], title: str) -> Figure | None:
    """Polar plot of the 1× unbalance response per sensor: amplitude [µm] at angle φ [°] (phase
    against roll angle 0) as the speed rises, vertical and horizontal, a few speeds labelled;
    None without a stored response over two or more speeds."""
    sensors = _responses(sys_)
    if not sensors or not _over_speed(sys_):
        return None
    speed = np.asarray(sys_["campbell/speed_hz"])
    fig = _figure(figsize=(4.6 * len(sensors) + 0.6, 5.2))
    for c, sensor in enumerate(sensors):
        ax = fig.add_subplot(1, len(sensors), c + 1, projection="polar")
        for d, colour in zip(DIRECTIONS, ("tab:orange", "tab:blue")):
            key = f"unbalance_response/{sensor}/{d}"
            amp = np.asarray(sys_[f"{key}/amplitude_um"])
            phi = np.radians(np.asarray(sys_[f"{key}/phase_deg"]))
            ax.plot(phi, amp, color=colour, marker=".", ms=3, label=d)
            # A few speeds labelled, among the points away from the centre (where they crowd).
            big = np.flatnonzero(amp >= POLAR_LABEL_SHARE * np.max(amp, initial=0.0))
            for i in big[np.unique(np.linspace(0, len(big) - 1, 6).round().astype(int))]:
                ax.annotate(f"{speed[i]:g}", (phi[i], amp[i]), fontsize="x-small", color=colour)
        ax.set_title(f"{sensor} [µm]; labels: speed [Hz]", fontsize="small", pad=16)
        ax.tick_params(labelsize="x-small")
    fig.axes[0].legend(fontsize="small", loc="lower left", bbox_to_anchor=(-0.15, -0.12))
    fig.suptitle(f"{title}: unbalance response (polar, phase against roll angle 0)")
    return fig


def critical_map(sys_: dict[str, object], title: str) -> Figure | None:
    """The undamped critical-speed map: the lowest :data:`MAX_MAP_CRITICALS` critical speeds
    [Hz] against the (isotropic) support stiffness [N/m], log–log, the actual supports' kx and
    ky marked; None without a stored map."""
    if "critical_map/critical_speeds_hz" not in sys_:
        return None
    k = np.asarray(sys_["critical_map/stiffness_n_per_m"])
    crit = np.asarray(sys_["critical_map/critical_speeds_hz"])[:, :MAX_MAP_CRITICALS]
    fig = _figure(figsize=(8.5, 5.5))
    ax = fig.subplots()
    for j in range(crit.shape[1]):
        ax.plot(k, crit[:, j], color=f"C{j}", marker=".", label=f"critical {j + 1}")
    nodes = list(sys_.get("critical_map/support_nodes", []))
    actual = {}
    for d, key in (("kx", "actual_kx_n_per_m"), ("ky", "actual_ky_n_per_m")):
        for node, value in zip(nodes, np.asarray(sys_.get(f"critical_map/{key}", []))):
            if value > 0:
                actual.setdefault(float(value), []).append(f"{node} {d}")
    for i, (value, who) in enumerate(sorted(actual.items())):
        ax.axvline(value, color="0.3", ls="--", lw=0.9)
        ax.annotate(f"actual: {', '.join(who)}\n{value:.3g} N/m", (value, 0.02 + 0.1 * i),
                    xycoords=("data", "axes fraction"), xytext=(4, 0),
                    textcoords="offset points", fontsize="x-small")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("support stiffness, every support isotropic [N/m]")
    ax.set_ylabel("undamped critical speed [Hz]")
    ax.grid(alpha=0.3, which="both")
    ax.yaxis.set_major_formatter(ScalarFormatter())
    ax.yaxis.set_minor_formatter(ScalarFormatter())
    ax.tick_params(axis="y", which="minor", labelsize="x-small")
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(f"{title}: critical-speed map")
    return fig


def floquet(sys_: dict[str, object], title: str) -> Figure | None:
    """The Floquet stability chart: −ln max|μ| of the monodromy over one revolution (a log
    decrement per revolution; < 0 unstable) over spin speed [Hz], symmetric-log scale, the
    unstable ranges shaded and the constant-coefficient stability threshold dashed; None without
    Floquet data at two or more speeds."""
    if "floquet/growth_per_rev" not in sys_:
        return None
    speed = np.asarray(sys_["floquet/speed_hz"])
    if speed.size < 2:
        return None
    decay = -np.asarray(sys_["floquet/growth_per_rev"])
    ranges = np.asarray(sys_.get("floquet/unstable_ranges_hz", np.zeros((0, 2)))).reshape(-1, 2)
    fig = _figure(figsize=(7.5, 5))
    ax = fig.subplots()
    ax.plot(speed, decay, color="tab:blue", marker=".", label="−ln max|μ| per revolution")
    for i, (a, b) in enumerate(ranges):
        ax.axvspan(a, b, color="tab:red", alpha=0.2,
                   label="Floquet-unstable" if i == 0 else None)
    threshold = sys_.get("stability_threshold_hz")
    if threshold is not None:
        ax.axvline(threshold, color="0.2", ls="--", lw=1,
                   label=f"threshold of the damped modes {threshold:.2f} Hz")
    ax.axhline(0.0, color="black", lw=0.8)
    small = np.abs(decay[decay != 0])
    ax.set_yscale("symlog", linthresh=float(np.min(small)) if small.size else 1e-6)
    ax.set_xlabel("spin speed [Hz]")
    ax.set_ylabel("−ln max|μ| per revolution (< 0: unstable)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="small")
    state = (f"unstable {', '.join(f'{a:.2f}–{b:.2f} Hz' for a, b in ranges)}"
             if len(ranges) else "stable at every speed")
    ax.set_title(f"{title}: Floquet stability over one revolution (body frame)\n{state}",
                 fontsize="medium")
    return fig


def linear_figures(systems: dict[str, dict[str, object]]) -> list[tuple[str, Figure | None]]:
    """The per-system figures (mode shapes, Bode, polar, critical-speed map, Floquet) of each
    system, named ``<figure>[-<system>].png`` (the suffix only with several systems)."""
    out: list[tuple[str, str, Figure]] = []
    for what in (mode_shapes, bode, polar, critical_map, floquet):
        for name, data in systems.items():
            fig = what(data, name)
            if fig is not None:
                out.append((what.__name__, name, fig))
    counts = pd.Series([w for w, _, _ in out]).value_counts()
    return [(f"{w}-{n}.png" if counts[w] > 1 else f"{w}.png", fig) for w, n, fig in out]

#: Colours of the runout directions in the order figures (as in the Bode plots).
DIRECTION_COLOURS = {"vertical": "tab:orange", "horizontal": "tab:blue"}


def ramp_jobs(path: PathLike) -> list[str]:
    """The jobs with a waterfall (``/jobs/<id>/waterfall``: speed changed while recording), in
    job-index order."""
    with h5py.File(path, "r") as f:
        return [i for i in rp.job_ids(path) if f"jobs/{i}/waterfall/freq_hz" in f]


def waterfall_data(path: PathLike, job: str) -> dict[str, np.ndarray]:
    """A ramp job's waterfall (src/study/orders.rs): ``time_s`` and ``speed_hz`` [blocks],
    ``freq_hz`` [bins] and ``map/<sensor>/<dir>`` [blocks × bins, µm]."""
    with h5py.File(path, "r") as f:
        g = f[f"jobs/{job}/waterfall"]
        data = {n: g[n][()] for n in ("time_s", "speed_hz", "freq_hz")}
        for sensor in g.get("map", {}):
            for d in g["map"][sensor]:
                data[f"map/{sensor}/{d}"] = g["map"][sensor][d][()]
    return data


def _job_title(study: str, what: str, name: str) -> str:
    return f"{study}: {what}" + (f"\n{name}" if name else "")


def waterfall(data: dict[str, np.ndarray], sensor: str, orders: list[float], study: str,
              name: str) -> Figure | None:
    """A ramp's waterfall of ``sensor``: the amplitude [µm, log colour scale spanning
    :data:`MAP_DECADES`] of Hanning spectra of half-overlapping time blocks over frequency [Hz]
    (rows: the blocks' mid time [s], the right axis their mean speed [Hz]), one panel per
    direction, with the order lines f = k·speed(t) of the tracked ``orders``; None without a map
    of that sensor or when it is zero."""
    dirs = [d for d in DIRECTIONS if f"map/{sensor}/{d}" in data]
    if not dirs or len(data["time_s"]) < 2:
        return None
    maps = [data[f"map/{sensor}/{d}"] for d in dirs]
    top = max(np.max(m, initial=0.0) for m in maps)
    if not top > 0:
        return None
    t, speed, freq = data["time_s"], data["speed_hz"], data["freq_hz"]
    norm = LogNorm(vmin=top / 10**MAP_DECADES, vmax=top, clip=True)
    fig = _figure(figsize=(5.6 * len(dirs) + 1.4, 6.2))
    axes = fig.subplots(1, len(dirs), sharey=True, squeeze=False)[0]
    for ax, d, m in zip(axes, dirs, maps):
        mesh = ax.pcolormesh(freq, t, m, norm=norm, cmap="viridis", shading="nearest",
                             rasterized=True)
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        for k in orders:
            ax.plot(k * speed, t, color="white", lw=0.8, alpha=0.5)
            inside = np.flatnonzero(k * speed <= x1)
            if inside.size:
                i = inside[np.argmax(t[inside])]
                ax.text(k * speed[i], t[i], f"{number_text(k)}×", color="white",
                        fontsize="small", ha="left", va="top")
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_title(f"{sensor} {d}", pad=8)
        ax.set_xlabel("frequency [Hz]")
    axes[0].set_ylabel("time, block middle [s]")
    # The speed of the blocks at the time ticks, on the right of the last panel.
    right = axes[-1].twinx()
    right.set_ylim(axes[-1].get_ylim())
    ticks = [y for y in axes[-1].get_yticks() if t[0] <= y <= t[-1]]
    right.set_yticks(ticks, [f"{np.interp(y, t, speed):.4g}" for y in ticks])
    right.set_ylabel("speed, block mean [Hz]")
    fig.colorbar(mesh, ax=[*axes, right], label="runout amplitude [µm]")
    fig.suptitle(_job_title(study, "waterfall (lines: tracked orders k·speed)", name))
    return fig


def _job_orders(orders: pd.DataFrame, job: str, sensor: str, d: str) -> pd.DataFrame:
    """The tracked blocks of one job and channel, in block (time) order."""
    rows = orders[(orders["job_id"] == job) & (orders["sensor"] == sensor)
                  & (orders["direction"] == d)]
    return rows.sort_values(["order", "block"])


def order_map(orders: pd.DataFrame, job: str, sensor: str, study: str,
              name: str) -> Figure | None:
    """A ramp's order map of ``sensor``: the tracked amplitude [µm, log] of each order over the
    blocks' mean speed [Hz], one line per order, one panel per direction; the order resonances
    of ``/analysis/order_resonances`` are the curves' peaks. None without tracked rows of that
    sensor."""
    dirs = [d for d in DIRECTIONS if not _job_orders(orders, job, sensor, d).empty]
    if not dirs:
        return None
    fig = _figure(figsize=(5.4 * len(dirs) + 0.8, 5.2))
    axes = fig.subplots(1, len(dirs), sharey=True, squeeze=False)[0]
    for ax, d in zip(axes, dirs):
        rows = _job_orders(orders, job, sensor, d)
        for i, (k, g) in enumerate(rows.groupby("order", sort=True)):
            amp = g["amplitude_um"].to_numpy()
            ax.plot(g["speed_hz"], np.where(amp > 0, amp, np.nan), color=f"C{i}",
                    marker=".", ms=2, lw=1, label=f"{number_text(float(k))}×")
        ax.set_yscale("log")
        ax.set_title(f"{sensor} {d}")
        ax.set_xlabel("speed, block mean [Hz]")
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel("order amplitude [µm]")
    axes[0].legend(title="order", fontsize="small")
    fig.suptitle(_job_title(study, "order map (tracked order amplitudes)", name))
    return fig


def _unwrap_deg(phase: np.ndarray) -> np.ndarray:
    """Unwrapped phase [°], NaN kept in place."""
    out = np.full(phase.shape, np.nan)
    ok = np.isfinite(phase)
    out[ok] = np.degrees(np.unwrap(np.radians(phase[ok])))
    return out


def _break_jumps(speed: np.ndarray, phase: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Speed and phase [°] with a NaN point after each phase step of more than 180° (a wrap,
    not drawn as a line)."""
    at = np.flatnonzero(np.abs(np.diff(phase)) > 180.0) + 1
    return np.insert(speed.astype(float), at, np.nan), np.insert(phase, at, np.nan)


def order_bode(orders: pd.DataFrame, job: str, linear: dict[str, object] | None, study: str,
               name: str) -> Figure | None:
    """Bode plot of a ramp's tracked 1× order per sensor (one column each, at most
    :data:`MAX_SENSORS`): amplitude [µm, log] and phase [°] (against roll angle 0) over the
    blocks' mean speed [Hz], vertical and horizontal; with ``linear`` (the job's
    ``/linear/<linear_id>`` system holding an unbalance response) the steady-state 1× unbalance
    response (phase unwrapped) dashed over it, each block's phase moved by whole turns nearest
    it, and the critical speeds dotted; without, the tracked phase unwrapped along the blocks
    and moved by whole turns to a median lag in (−360°, 0]. Steps over 180° are not joined.
    None without tracked 1× rows."""
    one = orders[orders["job_id"].eq(job) & np.isclose(orders["order"], 1.0)]
    sensors = list(dict.fromkeys(one["sensor"]))[:MAX_SENSORS]
    if not sensors:
        return None
    have_linear = linear is not None and bool(_responses(linear))
    fig = _figure(figsize=(max(4.6 * len(sensors) + 0.6, 7.0), 6.4))
    axes = fig.subplots(2, len(sensors), sharex=True, squeeze=False)
    for c, sensor in enumerate(sensors):
        for d in DIRECTIONS:
            rows = _job_orders(one, job, sensor, d)
            if rows.empty:
                continue
            colour = DIRECTION_COLOURS[d]
            speed = rows["speed_hz"].to_numpy()
            phase = _unwrap_deg(rows["phase_deg"].to_numpy())
            key = f"unbalance_response/{sensor}/{d}"
            if have_linear and f"{key}/amplitude_um" in linear:
                lin_speed = np.asarray(linear["campbell/speed_hz"])
                lin_amp = np.asarray(linear[f"{key}/amplitude_um"])
                lin_phase = _unwrap_deg(
                    np.where(lin_amp > 0, np.asarray(linear[f"{key}/phase_deg"]), np.nan))
                axes[0, c].plot(lin_speed, lin_amp, color=colour, ls="--", lw=1,
                                label=f"{d}, steady state (linear)")
                axes[1, c].plot(lin_speed, lin_phase, color=colour, ls="--", lw=1)
                # Each block's phase by whole turns nearest the steady state's at its speed.
                ref = np.interp(speed, lin_speed, lin_phase)
                phase = np.where(np.isfinite(ref), phase + 360.0 * np.round((ref - phase) / 360.0),
                                 phase)
            else:
                # Whole turns that put the median in (−360°, 0], a phase lag.
                phase = phase - 360.0 * np.ceil(np.nanmedian(phase) / 360.0)
            axes[0, c].plot(speed, rows["amplitude_um"], color=colour, lw=1.3,
                            label=f"{d}, tracked")
            axes[1, c].plot(*_break_jumps(speed, phase), color=colour, lw=1.0, marker=".", ms=2)
        axes[0, c].set_title(sensor)
        axes[1, c].set_xlabel("speed, block mean [Hz]")
        for ax in axes[:, c]:
            if have_linear:
                _mark_criticals(ax, linear)
            ax.grid(alpha=0.3)
    for ax in axes[0]:
        ax.set_yscale("log")
    axes[0, 0].set_ylabel("1× amplitude [µm], log")
    axes[1, 0].set_ylabel("1× phase [°] (x = A cos(θ + φ))")
    if have_linear:
        axes[0, 0].plot([], [], color="tab:red", lw=0.8, ls=":", label="critical speeds")
    axes[0, 0].legend(fontsize="small")
    what = "order-tracked 1× (Bode)" + (" and steady state" if have_linear else "")
    fig.suptitle(_job_title(study, what, name))
    return fig


def ramp_figures(path: PathLike, orders: pd.DataFrame, sensor: str | None, names: pd.Series,
                 study: str) -> list[tuple[str, Figure | None]]:
    """Per ramp job (:func:`ramp_jobs`) its waterfall, order map and order Bode plot, named
    ``waterfall[-<job>].png``, ``order_map[-<job>].png``, ``order_bode[-<job>].png`` (the
    suffix only with several ramp jobs), titled by the job's setting ``names``; ``orders`` is
    the ``/analysis/orders`` table. The waterfall and order map draw ``sensor``; None: "centre"
    where the job has it, else its first sensor."""
    jobs = ramp_jobs(path)
    if not jobs:
        return []
    attrs = rp.job_attrs(path)
    systems = _linear_systems(path)
    out: list[tuple[str, Figure | None]] = []
    for job in jobs:
        suffix = f"-{job}" if len(jobs) > 1 else ""
        name = str(names.get(job, job))
        tracked = sorted(set(orders.loc[orders["job_id"] == job, "order"])) if not orders.empty \
            else []
        data = waterfall_data(path, job)
        sensors = list(dict.fromkeys(k.split("/")[1] for k in data if k.startswith("map/")))
        which = sensor or ("centre" if "centre" in sensors or not sensors else sensors[0])
        out.append((f"waterfall{suffix}.png", waterfall(data, which, tracked, study, name)))
        if orders.empty:
            continue
        linear_id = attrs.at[job, "linear_id"] if "linear_id" in attrs else None
        linear = systems.get(linear_id) if isinstance(linear_id, str) else None
        out.append((f"order_map{suffix}.png", order_map(orders, job, which, study, name)))
        out.append((f"order_bode{suffix}.png", order_bode(orders, job, linear, study, name)))
    return out



def read_balance(path: PathLike) -> dict[str, object]:
    """The output of ``rotorsweep balance OUT.h5 --json`` (``corrections``, ``predicted`` and,
    with ``--check``, ``check``); :class:`PlotError` naming the file when it is not one."""
    try:
        data = json.loads(Path(path).read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise PlotError(f"{path}: not the JSON of `rotorsweep balance --json`: {e}") from None
    rows = data.get("predicted") if isinstance(data, dict) else None
    if not isinstance(rows, list) or not rows or not isinstance(data.get("corrections"), list):
        raise PlotError(f"{path}: not the JSON of `rotorsweep balance --json` (no 'corrections' "
                        "and 'predicted' lists)")
    need = {"speed_hz", "sensor", "direction", "before_um", "after_um"}
    for key in ("predicted", "check"):
        for i, row in enumerate(data.get(key) or []):
            if not isinstance(row, dict) or not need <= set(row):
                raise PlotError(f"{path}: {key}[{i}] lacks one of {', '.join(sorted(need))}")
    return data


def balancing(data: dict[str, object], study: str) -> Figure:
    """Balancing before and after per sensor: bars of the 1× amplitude [µm, log] at each sensor
    and direction, one panel per speed: the reference run (before), the influence coefficients'
    prediction after the corrections and, when ``data`` has ``check``, the check run of the
    corrected roll with its reduction [%]; the corrections in the title."""
    pred = pd.DataFrame(data["predicted"])
    check = pd.DataFrame(data.get("check") or [])
    speeds = sorted(pred["speed_hz"].unique())
    fig = _figure(figsize=(max(4.2 * len(speeds) + 0.8, 7.0), 5.4))
    axes = fig.subplots(1, len(speeds), sharey=True, squeeze=False)[0]
    for ax, speed in zip(axes, speeds):
        rows = pred[pred["speed_hz"] == speed].reset_index(drop=True)
        names = rows["sensor"] + "\n" + rows["direction"]
        x = np.arange(len(rows))
        series = [("before (reference run)", rows["before_um"], "0.55"),
                  ("after, predicted", rows["after_um"], "tab:blue")]
        if not check.empty:
            done = rows.merge(check[check["speed_hz"] == speed], how="left",
                              on=["speed_hz", "sensor", "direction"], suffixes=("", "_check"))
            series.append(("after, check run", done["after_um_check"], "tab:green"))
        width = 0.8 / len(series)
        for i, (label, values, colour) in enumerate(series):
            ax.bar(x + (i - (len(series) - 1) / 2) * width, values, width, color=colour,
                   label=label)
        if not check.empty:
            for xi, b, a in zip(x, done["before_um_check"], done["after_um_check"]):
                if b > 0 and np.isfinite(a):
                    ax.annotate(f"−{100 * (1 - a / b):.1f} %", (xi, b), xytext=(0, 2),
                                textcoords="offset points", ha="center", fontsize="x-small")
        ax.set_xticks(x, names, fontsize="small")
        ax.set_yscale("log")
        ax.set_title(f"{number_text(float(speed))} Hz")
        ax.grid(alpha=0.3, axis="y", which="both")
    axes[0].set_ylabel("1× runout amplitude [µm], log")
    axes[0].legend(fontsize="small")
    masses = "; ".join(f"z {float(c['z_mm']):g} mm: {float(c['mass_g']):.0f} g at "
                       f"{float(c['angle_deg']):.1f}°" for c in data["corrections"])
    fig.suptitle(f"{study}: balancing before and after\ncorrections {masses}",
                 fontsize="medium")
    return fig


def _check_tracked(path: PathLike) -> None:
    """Raises :class:`PlotError` naming ``path`` unless it is a rotorsweep HDF5 file with an
    order-tracking table (``/analysis/orders``: a study's, ``simulate -o``'s or ``import``'s)."""
    if not Path(path).is_file():
        raise PlotError(f"{path}: no such file")
    try:
        with h5py.File(path, "r") as f:
            ok = f.attrs.get("tool") == "rotorsweep" and "analysis/orders" in f
    except OSError as e:
        raise PlotError(f"{path}: not an HDF5 file ({e})") from None
    if not ok:
        raise PlotError(f"{path}: not a rotorsweep results file with order tracking (no "
                        "/analysis/orders: `rotorsweep import`, `simulate -o` or `run` of a ramp "
                        "writes one)")


def _single_ramp(path: PathLike) -> str:
    """The one ramp job of ``path`` (a measured record or the model's run-up it is compared
    with); :class:`PlotError` for none or several."""
    jobs = ramp_jobs(path)
    if len(jobs) != 1:
        raise PlotError(f"{path}: {len(jobs)} jobs whose speed changes; the comparison takes a "
                        "file of one run-up or coast-down (rotorsweep import, simulate -o)")
    return jobs[0]


def compare_waterfalls(measured: dict[str, np.ndarray], simulated: dict[str, np.ndarray],
                       sensor: str, orders: list[float], title: str) -> Figure | None:
    """Measured and simulated waterfalls of ``sensor`` side by side (columns), a row per
    direction, over frequency [Hz] and the blocks' mean speed [Hz] (so that records starting at
    different times line up), on one log colour scale spanning :data:`MAP_DECADES` below the
    larger maximum, with the tracked orders' lines f = k·speed. None when neither has that
    sensor."""
    dirs = [d for d in DIRECTIONS
            if f"map/{sensor}/{d}" in measured and f"map/{sensor}/{d}" in simulated]
    if not dirs:
        return None
    top = max(np.max(data[f"map/{sensor}/{d}"], initial=0.0)
              for data in (measured, simulated) for d in dirs)
    if not top > 0:
        return None
    norm = LogNorm(vmin=top / 10**MAP_DECADES, vmax=top, clip=True)
    fig = _figure(figsize=(11.5, 4.6 * len(dirs) + 0.8))
    axes = fig.subplots(len(dirs), 2, sharex=True, sharey=True, squeeze=False)
    mesh = None
    for row, d in zip(axes, dirs):
        for ax, (what, data) in zip(row, (("measured", measured), ("simulated", simulated))):
            speed, freq = data["speed_hz"], data["freq_hz"]
            mesh = ax.pcolormesh(freq, speed, data[f"map/{sensor}/{d}"], norm=norm,
                                 cmap="viridis", shading="nearest", rasterized=True)
            for k in orders:
                ax.plot(k * speed, speed, color="white", lw=0.8, alpha=0.5)
            ax.set_title(f"{what}: {sensor} {d}")
        row[0].set_ylabel("speed, block mean [Hz]")
    # The range both maps cover (each file's own cap follows its tracked orders).
    right = min(float(measured["freq_hz"][-1]), float(simulated["freq_hz"][-1]))
    for ax in axes[-1]:
        ax.set_xlabel("frequency [Hz]")
        ax.set_xlim(0.0, right)
    fig.colorbar(mesh, ax=axes.ravel().tolist(), label="runout amplitude [µm]")
    fig.suptitle(f"{title}: waterfalls, measured | simulated (lines: tracked orders k·speed)")
    return fig


def compare_orders(measured: pd.DataFrame, simulated: pd.DataFrame, sensor: str,
                   title: str) -> Figure | None:
    """The tracked order amplitudes [µm, log] of ``sensor`` over speed [Hz] in block (time) order
    (a measured record's block speeds scatter with its keyphasor's timing), measured (solid,
    dots) and simulated (dashed) in one colour per order tracked in both, a panel per direction.
    None when the two share no order of that sensor."""
    dirs = [d for d in DIRECTIONS
            if not measured[(measured["sensor"] == sensor) & (measured["direction"] == d)].empty]
    shared = sorted(set(measured["order"]) & set(simulated["order"]))
    if not dirs or not shared:
        return None
    fig = _figure(figsize=(5.6 * len(dirs) + 0.8, 5.4))
    axes = fig.subplots(1, len(dirs), sharey=True, squeeze=False)[0]
    for ax, d in zip(axes, dirs):
        for i, k in enumerate(shared):
            for rows, style in ((measured, dict(ls="-", marker=".", ms=3)),
                                (simulated, dict(ls="--"))):
                g = rows[(rows["sensor"] == sensor) & (rows["direction"] == d)
                         & (rows["order"] == k)].sort_values("block")
                amp = g["amplitude_um"].to_numpy()
                ax.plot(g["speed_hz"], np.where(amp > 0, amp, np.nan), color=f"C{i}", lw=1,
                        **style)
        ax.set_yscale("log")
        ax.set_title(f"{sensor} {d}")
        ax.set_xlabel("speed, block mean [Hz]")
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel("order amplitude [µm]")
    handles = [Patch(color=f"C{i}", label=f"{number_text(float(k))}×")
               for i, k in enumerate(shared)]
    handles += [axes[0].plot([], [], color="k", ls="-", marker=".", label="measured")[0],
                axes[0].plot([], [], color="k", ls="--", label="simulated")[0]]
    axes[0].legend(handles=handles, fontsize="small")
    fig.suptitle(f"{title}: tracked order amplitudes, measured vs simulated")
    return fig


def compare_figures(measured: PathLike, simulated: PathLike,
                    sensor: str | None) -> list[tuple[str, Figure | None]]:
    """``compare_waterfall.png`` and ``compare_orders.png``: the one ramp job of the measured
    file against the one of the simulated file (``rotorsweep report MEASURED --compare
    SIMULATED``'s pair), for ``sensor`` (None: "centre" where the measured record has it, else
    its first sensor)."""
    for f in (measured, simulated):
        _check_tracked(f)
    mjob, sjob = _single_ramp(measured), _single_ramp(simulated)
    mdata, sdata = waterfall_data(measured, mjob), waterfall_data(simulated, sjob)
    sensors = list(dict.fromkeys(k.split("/")[1] for k in mdata if k.startswith("map/")))
    which = sensor or ("centre" if "centre" in sensors or not sensors else sensors[0])
    if which not in sensors:
        raise PlotError(f"{measured}: no sensor {which!r} (there are: {', '.join(sensors)})")
    morders = rp.analysis_table(measured, "orders")
    sorders = rp.analysis_table(simulated, "orders")
    morders = morders[morders["job_id"] == mjob]
    sorders = sorders[sorders["job_id"] == sjob]
    title = f"{Path(measured).name} vs {Path(simulated).name}"
    tracked = sorted(set(morders["order"])) if not morders.empty else []
    out: list[tuple[str, Figure | None]] = [
        ("compare_waterfall.png", compare_waterfalls(mdata, sdata, which, tracked, title))]
    if not morders.empty and not sorders.empty:
        out.append(("compare_orders.png", compare_orders(morders, sorders, which, title)))
    return out


def render(path: PathLike, outdir: PathLike, channel: str | None = None,
           balance: PathLike | None = None, compare: PathLike | None = None) -> list[Path]:
    """Writes the plots the results file ``path`` has data for into ``outdir`` (created if
    needed) and returns their paths, in the order of the module doc. ``channel`` is
    "SENSOR/DIR" (not used for a ``rotorsweep linear -o`` file); None: "centre/vertical", and
    each ramp job's first sensor where it has no "centre". ``balance``: the output of
    ``rotorsweep balance path --json``, drawn as ``balancing.png`` (study files only).
    ``compare``: a simulated results file that ``path`` (a measured record) is compared with
    (:func:`compare_figures`). Raises :class:`PlotError` when ``path`` is neither a study
    results file nor a ``linear -o`` file, has no such channel, ``balance`` is not such output,
    or ``path`` and ``compare`` are not one ramp job each."""
    if compare is not None:
        if balance is not None:
            raise PlotError("--compare and --balance are for different files: one at a time")
        figures = compare_figures(path, compare, None if channel is None
                                  else channel.partition("/")[0])
        Path(outdir).mkdir(parents=True, exist_ok=True)
        return [_save(fig, Path(outdir) / name) for name, fig in figures if fig is not None]
    study_file = check_results_file(path)
    balanced = None if balance is None else read_balance(balance)
    if balanced is not None and not study_file:
        raise PlotError(f"{balance}: balancing needs a study results file, not {path}")
    chosen = channel is not None
    channel = channel if chosen else DEFAULT_CHANNEL
    sensor, _, direction = channel.partition("/")
    if direction not in DIRECTIONS:
        raise PlotError(f"channel {channel!r}: expected SENSOR/DIR, DIR {' or '.join(DIRECTIONS)}")
    out = Path(outdir)
    if not study_file:
        systems = _linear_systems(path)
        figures = [("campbell.png", campbell([(n if len(systems) > 1 else "", d)
                                               for n, d in systems.items()],
                                              ", ".join(systems)))]
        out.mkdir(parents=True, exist_ok=True)
        figures += linear_figures(systems)
        return [_save(fig, out / name) for name, fig in figures if fig is not None]
    summary = rp.load_summary(path)
    varying = rp.varying_keys(path)
    labels = rp.job_labels(path)
    study = str(rp.file_attrs(path).get("study_name", Path(path).stem))
    sweeps = rp.sweeps(path)
    trial = rp.analysis_table(path, "trial_mass")
    orders = rp.analysis_table(path, "orders")
    tracked = set() if not chosen or orders.empty else set(
        orders["sensor"] + "/" + orders["direction"])
    have = sorted({c for s in sweeps for c in s["lines"]} | set(trial.get("channel", []))
                  | tracked)
    if have and channel not in have:
        raise PlotError(f"{path}: no channel {channel!r} (there are: {', '.join(have)})")
    out.mkdir(parents=True, exist_ok=True)
    attrs = rp.job_attrs(path)
    figures: list[tuple[str, Figure | None]] = []
    for s in sweeps:
        suffix = f"-{s['n']}" if len(sweeps) > 1 else ""
        ratios = roller_ratios(attrs, s["job_ids"])
        means = sweep_means(path, s["n"])
        figures.append((f"spectral_map{suffix}.png",
                        spectral_map(s, sensor, study, ratios, mean_removed=bool(means))))
        figures.append((f"harmonics{suffix}.png", harmonics(s, sensor, study)))
        figures.append((f"mean{suffix}.png", mean_runout(s, means, study)))
    if not trial.empty:
        names = settings(summary, labels, [k for k in varying if k != "speed.hz"])
        figures.append(("trial_mass.png", trial_mass(trial, names, direction, study)))
    physics = [k for k in varying if k != "speed.hz" and not k.startswith("solver.")]
    if (summary["status"].isin(COMPLETED) & (summary["error_max_um"] > 0)).any():
        reference = attrs["reference_id"]
        solver_keys = [k for k in varying if k.startswith(("solver.", "reduction."))]
        physics_keys = [k for k in varying if k not in solver_keys]
        # The integrator has its colour; the points name the rest of the solver setting (by
        # the axis's label where the integrator's axis has labels).
        if "solver.integrator" not in labels.columns:
            solver_keys = [k for k in solver_keys if k != "solver.integrator"] or solver_keys
        # The same physics: the same values of the other keys (a labelled axis may zip solver
        # keys with physics keys; its labels then tell settings, not physics, apart).
        same = summary.set_index("job_id")[physics_keys].astype(str).agg("|".join, axis=1)
        figures.append(("work_precision.png", work_precision(
            summary, reference, study, settings(summary, labels, solver_keys),
            settings(summary, labels, physics_keys), same)))
    if len(summary) > 0:
        figures.append(("timing.png", timing(summary, settings(summary, labels, varying), study)))
    if "solver.integrator" in varying and len(varying) > 1:
        names = settings(summary, labels, [k for k in varying if k != "solver.integrator"])
        figures.append(("stability.png", stability(summary, names, study)))
    names = settings(summary, labels, physics)
    figures.append(("campbell.png", campbell(_study_systems(path, names), study)))
    figures += linear_figures(_linear_systems(path))
    figures += ramp_figures(path, orders, sensor if chosen else None,
                            settings(summary, labels, varying), study)
    if balanced is not None:
        figures.append(("balancing.png", balancing(balanced, study)))
    return [_save(fig, out / name) for name, fig in figures if fig is not None]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(
        description="PNG plots of a rotorsweep study results file (spectral maps, harmonics, "
        "trial-mass response, work-precision, timing, stability, Campbell; per ramp job a "
        "waterfall, order map and order-tracked Bode plot) or of a "
        "`rotorsweep linear -o` file (Campbell, mode shapes, Bode, polar, critical-speed map, "
        "Floquet)."
    )
    p.add_argument(
        "results", type=Path, help="results file of `rotorsweep run`, `merge` or `linear -o`"
    )
    p.add_argument(
        "-o", "--outdir", type=Path, help="folder for the PNGs (default: OUT-plots beside OUT.h5)"
    )
    p.add_argument(
        "--channel",
        help="SENSOR/DIR: the sensor of the spectral maps and harmonics (both directions drawn) "
        "and the direction of the trial-mass panels, and the sensor of the ramps' waterfalls "
        "and order maps (default: centre/vertical; for a ramp without a centre sensor its "
        "first sensor)",
    )
    p.add_argument(
        "--balance",
        type=Path,
        metavar="JSON",
        help="the output of `rotorsweep balance RESULTS --json [--check]`: also draws "
        "balancing.png (1x before and after per sensor and speed)",
    )
    p.add_argument(
        "--compare",
        type=Path,
        metavar="SIMULATED.h5",
        help="a simulated run-up to compare RESULTS (a measured record, `rotorsweep import`) "
        "with: also draws compare_waterfall.png (waterfalls side by side) and "
        "compare_orders.png (order amplitudes over speed, measured and simulated)",
    )
    a = p.parse_args(argv)
    outdir = a.outdir or a.results.with_name(a.results.stem + "-plots")
    try:
        written = render(a.results, outdir, a.channel, a.balance, a.compare)
    except PlotError as e:
        print(f"plots.py: error: {e}", file=sys.stderr)
        return 1
    for w in written:
        print(w)
    return 0


if __name__ == "__main__":
    sys.exit(main())
