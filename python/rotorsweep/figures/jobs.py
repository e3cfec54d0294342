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
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from ._common import COMPLETED, figure, significant

#: Up to this many jobs the timing chart has vertical bars; above, one horizontal bar a job.
MAX_TIMING_JOBS = 12
#: Fill colour of each job status.
STATUS_COLOURS = {"ok": "#9ccc65", "untrusted": "#fff176", "diverged": "#ef5350", "budget": "#ffb74d"}
#: Markers of the integrators in the work-precision chart, in turn.
MARKERS = "osD^v<>"
#: Most physics panels in one work-precision figure (3 a row); more physics go on further
#: figures of as many panels (:func:`work_precision_pages`), each panel as readable as in the first.
MAX_WORK_PANELS = 12


def work_precision(
    summary: pd.DataFrame,
    reference: pd.Series,
    study: str,
    solver: pd.Series | None = None,
    physics: pd.Series | None = None,
    physics_id: pd.Series | None = None,
    integrators: list[str] | None = None,
    page: tuple[int, int] = (1, 1),
) -> Figure:
    """Runout error against the reference (error_max_um) over CPU time, log–log: one panel per
    physics (``physics_id``: a value per job_id that is the same for the same physics, by
    default ``physics``; every physics of ``summary`` gets its panel, 3 a row, so keep to
    :data:`MAX_WORK_PANELS` — :func:`work_precision_pages` splits more), titled with its jobs'
    ``physics`` (text per job_id of the keys that change the physics, several joined by " / "),
    one colour and marker per integrator (in the order ``integrators``, default the order of
    ``summary``: pages of one study pass the study's so that colours agree), every job a marker
    labelled with its solver setting (``solver``: text per job_id); per integrator and reference
    run (``reference``: reference_id per job_id) a line through its work-precision front (the
    jobs more accurate than every cheaper one). Up to 3 panels (one row) each has a legend
    counting its jobs shown and failed; more are drawn compact, with one legend of the
    integrators for the figure and, in a panel, a red note of its failed or untrusted jobs. ``page``: (this figure's number, of how many), in the title when more than one."""
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
    rows, cols = (len(groups) + 2) // 3, min(len(groups), 3)
    # One panel wide, so that its labels have room; one row at 6 inches a panel, each with its
    # legend; more rows compact (4.6 × 3.9 inches, MAX_WORK_PANELS in 14 × 16 inches), the axis
    # titles on the outer panels only and one legend of the integrators for the figure.
    compact = rows > 1
    width, height = (8.5, 6.2) if len(groups) == 1 else (4.6, 3.9) if compact else (6.0, 5.0)
    fig = figure(figsize=(width * cols + 0.5, height * rows + (1.0 if compact else 0.4)))
    axes = fig.subplots(rows, cols, squeeze=False).ravel()
    integrators = integrators or list(dict.fromkeys(summary["integrator"]))
    for n, (ax, group) in enumerate(zip(axes, groups)):
        jobs_here = summary[summary["physics_id"] == group]
        title = " / ".join(p for p in dict.fromkeys(jobs_here["physics"]) if p)
        if len(groups) > 1 and title:
            ax.set_title(title, fontsize="medium")
        drawn = jobs_here["status"].isin(COMPLETED) & (jobs_here["error_max_um"] > 0)
        if not drawn.any():
            failed = ", ".join(f"{i}: {s}" for i, s in zip(jobs_here["integrator"],
                                                           jobs_here["status"]))
            ax.text(0.5, 0.5, f"no job with an error to draw\n({failed})", ha="center",
                    va="center", transform=ax.transAxes, fontsize="small", wrap=True)
            ax.set_xticks([])
            ax.set_yticks([])
            continue
        notes = []
        for integrator, jobs in jobs_here.groupby("integrator", sort=False):
            i = integrators.index(integrator)
            shown = jobs[jobs["status"].isin(COMPLETED) & (jobs["error_max_um"] > 0)]
            note = _job_count(jobs, shown)
            style = {"color": f"C{i}", "marker": MARKERS[i % len(MARKERS)]}
            if compact:
                if len(shown) < len(jobs) or (jobs["status"] == "untrusted").any():
                    notes.append(f"{integrator}: {note}")
            else:
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
        ax.grid(alpha=0.3, which="both")
        if not compact:
            ax.set_xlabel("CPU time [s]")
            ax.set_ylabel("runout error against the reference, max [µm]")
            ax.legend(fontsize="small")
            continue
        if n % cols == 0:
            ax.set_ylabel("max runout error [µm]")
        if n + cols >= len(groups):
            ax.set_xlabel("CPU time [s]")
        if notes:
            ax.text(0.02, 0.02, "\n".join(notes), transform=ax.transAxes, fontsize="x-small",
                    va="bottom", color="tab:red")
    for ax in axes[len(groups):]:
        ax.set_visible(False)
    what = "work-precision" + (" per physics" if len(groups) > 1 else "")
    of = f", figure {page[0]} of {page[1]}" if page[1] > 1 else ""
    if compact:
        # One legend for all panels: each integrator with its jobs shown of all on this figure.
        handles = []
        for integrator, jobs in summary.groupby("integrator", sort=False):
            i = integrators.index(integrator)
            shown = jobs[jobs["status"].isin(COMPLETED) & (jobs["error_max_um"] > 0)]
            handles.append(Line2D([], [], color=f"C{i}", marker=MARKERS[i % len(MARKERS)],
                                  label=f"{integrator} ({_job_count(jobs, shown)})"))
        fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 4),
                   fontsize="small")
    fig.suptitle(f"{study}: {what} (labels: solver setting{of})")
    return fig


def _job_count(jobs: pd.DataFrame, shown: pd.DataFrame) -> str:
    """"n of m jobs", with the untrusted and the failed among them when there are."""
    failed = int((~jobs["status"].isin(COMPLETED)).sum())
    untrusted = int((jobs["status"] == "untrusted").sum())
    return (f"{len(shown)} of {len(jobs)} jobs" + (f", {untrusted} untrusted" if untrusted else "")
            + (f", {failed} failed" if failed else ""))


def work_precision_pages(
    summary: pd.DataFrame,
    reference: pd.Series,
    study: str,
    solver: pd.Series | None = None,
    physics: pd.Series | None = None,
    physics_id: pd.Series | None = None,
) -> list[Figure]:
    """:func:`work_precision` of every physics, :data:`MAX_WORK_PANELS` panels a figure (in the
    order of ``summary``), however many physics there are: one figure up to that many, then as
    many figures as needed, with the same colour per integrator on each."""
    ids = summary["job_id"]
    key = (physics if physics_id is None else physics_id)
    key = pd.Series("", index=ids.to_numpy()) if key is None else key.loc[ids]
    groups = list(dict.fromkeys(key))
    pages = [groups[i:i + MAX_WORK_PANELS] for i in range(0, len(groups), MAX_WORK_PANELS)]
    integrators = list(dict.fromkeys(summary["integrator"]))
    return [
        work_precision(summary[key.isin(chunk).to_numpy()], reference, study, solver, physics,
                       physics_id, integrators, (n, len(pages)))
        for n, chunk in enumerate(pages, 1)
    ]


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
        error = f"{significant(job['error_max_um'], 3)} µm" if np.isfinite(job["error_max_um"]) \
            else "–"
        head = "" if job["status"] == "ok" else f"{job['status']}\n"
        text.setdefault((r, c), []).append(f"{head}{error}\n{significant(job['cpu_time_s'], 3)} s")
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
