"""The figures of a study's jobs side by side (``/summary`` and the jobs' attributes): the
work-precision chart (runout error [µm] over CPU time [s]), the CPU time per job [s] and the
stability matrix (integrator × setting, coloured by the report's error class)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.colors import to_rgb
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from ._common import COMPLETED, figure

#: Up to this many jobs the timing chart has vertical bars; above, one horizontal bar a job.
MAX_TIMING_JOBS = 12
#: Fill colour of each job status.
STATUS_COLOURS = {"ok": "#9ccc65", "untrusted": "#fff176", "diverged": "#ef5350", "budget": "#ffb74d"}
#: Markers of the integrators in the work-precision chart, in turn.
MARKERS = "osD^v<>"
#: Most physics panels of the work-precision figure (more: one panel, a marker per physics).
MAX_WORK_PANELS = 9


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
    fig = figure(figsize=(width * min(len(groups), 3) + 0.5,
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
        fig = figure(figsize=(max(6.5, 0.9 * len(summary) + 2), 5.5))
        ax = fig.subplots()
        bars = ax.bar(x, cpu, color=colours)
        ax.set_xticks(x, ticks, rotation=30, ha="right", fontsize="small")
        ax.set_ylabel("CPU time [s]")
        ax.margins(y=0.12)
    else:
        longest = max((len(t) for t in ticks), default=10)
        fig = figure(figsize=(7.5 + 0.06 * longest, 0.19 * len(summary) + 1.6))
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


def stability(summary: pd.DataFrame, names: pd.Series, study: str, classes: pd.Series,
              colours: Mapping[str, str]) -> Figure:
    """A matrix integrator (rows) × setting (columns, ``names``: text per job of the other
    varying keys) coloured by each job's error class (``classes``: text per job_id, the
    report's ``error_class``) in its colour (``colours``: class → colour from the best class to
    the worst, the report's ``labels.error_classes``; a class not there is grey and worst), each
    cell with the status when not ok, error_max_um [µm] and cpu_time_s [s]; several jobs in one
    cell take the worst class."""
    df = summary.assign(setting=names.loc[summary["job_id"]].to_numpy())
    rows = list(dict.fromkeys(df["integrator"]))
    cols = list(dict.fromkeys(df["setting"]))
    order = list(colours)

    def rank(cls: str) -> int:
        return order.index(cls) if cls in order else len(order)

    worst: dict[tuple[int, int], str] = {}
    text: dict[tuple[int, int], list[str]] = {}
    for _, job in df.iterrows():
        r, c = rows.index(job["integrator"]), cols.index(job["setting"])
        cls = str(classes[job["job_id"]])
        if (r, c) not in worst or rank(cls) > rank(worst[(r, c)]):
            worst[(r, c)] = cls
        error = f"{job['error_max_um']:.3g} µm" if np.isfinite(job["error_max_um"]) else "–"
        head = "" if job["status"] == "ok" else f"{job['status']}\n"
        text.setdefault((r, c), []).append(f"{head}{error}\n{job['cpu_time_s']:.3g} s")
    rgb = np.ones((len(rows), len(cols), 3))
    for (r, c), cls in worst.items():
        rgb[r, c] = to_rgb(colours.get(cls, "lightgrey"))
    fig = figure(figsize=(max(5.5, 1.5 * len(cols) + 3.5), 1.1 * len(rows) + 2.8))
    ax = fig.subplots()
    ax.imshow(rgb, aspect="auto")
    for (r, c), lines in text.items():
        ax.text(c, r, "\n".join(lines), ha="center", va="center", fontsize="small")
    ax.set_xticks(range(len(cols)), cols, rotation=30, ha="right", fontsize="small")
    ax.set_yticks(range(len(rows)), rows)
    used = sorted(set(worst.values()), key=lambda c: (rank(c), c))
    handles = [Patch(color=colours.get(c, "lightgrey"), label=c) for c in used]
    ax.legend(handles=handles, title="max error / status", fontsize="small",
              loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(f"{study}: error class, max error and CPU time per integrator and setting")
    return fig
