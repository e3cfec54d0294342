"""Which figures a file gets, in which order, under which names (:func:`render`), and the command
line (:func:`main`, ``python -m rotorsweep.figures``; the package doc describes both)."""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import threading
from pathlib import Path

import pandas as pd
from matplotlib.figure import Figure

import rotorsweep as rp
from rotorsweep import PathLike

from ._common import (
    COMPLETED,
    DEFAULT_CHANNEL,
    DIRECTIONS,
    PlotError,
    file_kind,
    save,
    settings,
)
from .balance import balancing, read_balance
from .calibration import calibration_figures
from .compare import compare_figures
from .jobs import stability, timing, work_precision_pages
from .linear import campbell, linear_figures, linear_groups, study_systems
from .barring import barring_frequency, barring_map
from .nips import has_nips, nip_orders, nip_profile, nip_spectrum
from .ramps import ramp_figures
from .sampled import sampled_figures
from .sweeps import harmonics, mean_runout, roller_ratios, spectral_map, sweep_means, trial_mass
from .tables import ReportTables

#: The program's name in its messages when run as a module.
PROG = "python -m rotorsweep.figures"


def _write(figures: list[tuple[str, Figure | None]], outdir: PathLike) -> list[Path]:
    """Saves the drawn figures (the None ones are not drawn) into ``outdir``, created only now
    (nothing is written when drawing failed); their paths in order."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    return [save(fig, out / name) for name, fig in figures if fig is not None]


def render(path: PathLike, outdir: PathLike, channel: str | None = None,
           balance: PathLike | None = None, compare: PathLike | None = None,
           tables: PathLike | None = None) -> list[Path]:
    """Writes the figures the results file ``path`` has data for into ``outdir`` (created if
    needed) and returns their paths, in the order of the package doc. ``channel`` is
    "SENSOR/DIR" (not used for a ``rotorsweep linear -o`` file); None: "centre/vertical", and
    each ramp job's first sensor where it has no "centre". ``balance``: the output of
    ``rotorsweep balance path --json``, drawn as ``balancing.png`` (study files only).
    ``compare``: a simulated results file that ``path`` (a measured record) is compared with
    (:func:`~.compare.compare_figures`). ``tables``: the JSON of ``rotorsweep report path
    --format json`` (with ``--compare``: of ``report path --compare COMPARE``); None: the binary
    prints it when a figure needs it (:mod:`.tables`). Raises :class:`PlotError` when ``path``
    is neither a study results file nor a ``linear -o`` file, has no such channel, ``balance``
    is not such output, ``path`` and ``compare`` are not one ramp job each, or the report's
    tables cannot be had or lack what a figure needs; nothing is written then."""
    if compare is not None:
        if balance is not None:
            raise PlotError("--compare and --balance are for different files: one at a time")
        report = ReportTables(path, compare, tables)
        figures = compare_figures(path, compare, None if channel is None
                                  else channel.partition("/")[0], report.numbers)
        return _write(figures, outdir)
    kind = file_kind(path)
    if kind == "barring":
        if balance is not None:
            raise PlotError(f"{balance}: balancing needs a study results file, not the "
                            f"barring map {path}")
        title = Path(path).stem
        return _write([("barring_map.png", barring_map(path, title)),
                       ("barring_frequency.png", barring_frequency(path, title))], outdir)
    if kind == "calibration":
        if balance is not None:
            raise PlotError(f"{balance}: balancing needs a study results file, not the "
                            f"calibration {path}")
        return _write(calibration_figures(path), outdir)
    study_file = kind == "study"
    balanced = None if balance is None else read_balance(balance)
    if balanced is not None and not study_file:
        raise PlotError(f"{balance}: balancing needs a study results file, not {path}")
    chosen = channel is not None
    channel = channel if chosen else DEFAULT_CHANNEL
    sensor, _, direction = channel.partition("/")
    if direction not in DIRECTIONS:
        raise PlotError(f"channel {channel!r}: expected SENSOR/DIR, DIR {' or '.join(DIRECTIONS)}")
    report = ReportTables(path, None, tables)
    if not study_file:
        systems = linear_groups(path)
        figures = [("campbell.png", campbell([(n if len(systems) > 1 else "", d)
                                               for n, d in systems.items()],
                                              ", ".join(systems)))]
        figures += linear_figures(systems)
        return _write(figures, outdir)
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
    if have and channel not in have and not chosen:
        # A machine's channels are named by roll (`reference.centre/vertical`): its first
        # roll's centre, else the first channel.
        channel = next((c for c in have if c.endswith("." + DEFAULT_CHANNEL)), have[0])
        sensor, _, direction = channel.partition("/")
    if have and channel not in have:
        raise PlotError(f"{path}: no channel {channel!r} (there are: {', '.join(have)})")
    numbers = report.numbers

    def names(keys: list[str]) -> pd.Series:
        return settings(summary, labels, keys, numbers)

    attrs = rp.job_attrs(path)
    figures: list[tuple[str, Figure | None]] = []
    for s in sweeps:
        suffix = f"-{s['n']}" if len(sweeps) > 1 else ""
        ratios = roller_ratios(attrs, s["job_ids"])
        means = sweep_means(path, s["n"])
        figures.append((f"spectral_map{suffix}.png",
                        spectral_map(s, sensor, study, ratios, report.roller_ratios,
                                     mean_removed=bool(means))))
        figures.append((f"harmonics{suffix}.png", harmonics(s, sensor, study, numbers)))
        figures.append((f"mean{suffix}.png", mean_runout(s, means, study)))
    if has_nips(path):
        doc = report.document()[0]
        speeds = attrs["speed_hz"] if "speed_hz" in attrs else pd.Series(dtype=float)
        nip_settings = names([k for k in varying if k != "speed.hz"])
        figures.append(("nip_orders.png", nip_orders(doc, speeds, nip_settings, study)))
        figures.append(("nip_spectrum.png", nip_spectrum(path, speeds, nip_settings, study)))
        figures.append(("nip_profile.png", nip_profile(doc, speeds, nip_settings, study)))
    if not trial.empty:
        figures.append(("trial_mass.png", trial_mass(
            trial, names([k for k in varying if k != "speed.hz"]), direction, study)))
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
        pages = work_precision_pages(summary, reference, study, names(solver_keys),
                                     names(physics_keys), same)
        figures += [(f"work_precision{f'-{n}' if n > 1 else ''}.png", fig)
                    for n, fig in enumerate(pages, 1)]
    sampled = "sample" in labels.columns
    # A bar a job: unreadable for the hundreds of jobs of a sampled study.
    if len(summary) > 0 and not sampled:
        figures.append(("timing.png", timing(summary, names(varying), study)))
    if "solver.integrator" in varying and len(varying) > 1:
        figures.append(("stability.png", stability(
            summary, names([k for k in varying if k != "solver.integrator"]), study,
            report.error_classes(list(summary["job_id"])), report.class_colours())))
    figures.append(("campbell.png", campbell(study_systems(path, names(physics)), study)))
    figures += linear_figures(linear_groups(path))
    # A sampled study (its jobs labelled by their design row, `label:sample`) gets the figures
    # of its distribution instead of one set of ramp figures per job.
    if sampled:
        figures += sampled_figures(report.document()[0], channel, study)
    else:
        figures += ramp_figures(path, orders, sensor if chosen else None, names(varying), study,
                                numbers)
    if balanced is not None:
        figures.append(("balancing.png", balancing(balanced, study, numbers)))
    return _write(figures, outdir)


def _end_with_parent(outdir: Path) -> None:
    """Ends this process, removing ``outdir``, when standard input reaches its end: the parent
    that holds it open has ended (``--until-stdin-closes``)."""

    def watch() -> None:
        # os.read on the descriptor, not sys.stdin: a daemon thread blocked in a buffered read
        # would hold its lock at interpreter shutdown.
        while os.read(0, 65536):
            pass
        shutil.rmtree(outdir, ignore_errors=True)
        os._exit(3)

    threading.Thread(target=watch, daemon=True).start()


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """The command line (the package doc): prints each written PNG's path on a line of its own,
    in the order written; exit code 0, 1 on a :class:`PlotError` (its message on standard error
    after ``PROG: error:``), 2 on a usage error (argparse's)."""
    p = argparse.ArgumentParser(
        prog=prog,
        description="PNG figures of a rotorsweep study results file (spectral maps, harmonics, "
        "trial-mass response, work-precision, timing, stability, Campbell; per ramp job a "
        "waterfall, order map and order-tracked Bode plot) or of a "
        "`rotorsweep linear -o` file (Campbell, mode shapes, Bode, polar, critical-speed map, "
        "Floquet), or of a `rotorsweep calibrate -o` file (target rows, records, residuals, "
        "cost and parameter paths). Prints the paths written, one a line.",
    )
    p.add_argument(
        "results", type=Path,
        help="results file of `rotorsweep run`, `merge`, `linear -o` or `calibrate -o`"
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
    p.add_argument(
        "--tables",
        type=Path,
        metavar="TABLES.json",
        help="the output of `rotorsweep report RESULTS --format json --labels` (with --compare: "
        "of `report RESULTS --compare SIMULATED.h5 --format json --labels`): the error classes "
        "and number "
        "text the figures write (default: run $ROTORSWEEP_BIN, else rotorsweep on PATH, else "
        "this source tree's target/release (or debug) rotorsweep, when a figure needs them)",
    )
    p.add_argument(
        "--until-stdin-closes",
        action="store_true",
        help="for a parent process (`rotorsweep report --format html`) that holds our standard "
        "input open while it waits: when it closes (the parent ended, or was killed), stop at "
        "once and remove OUTDIR (the parent's scratch folder, with all in it)",
    )
    a = p.parse_args(argv)
    outdir = a.outdir or a.results.with_name(a.results.stem + "-plots")
    if a.until_stdin_closes:
        _end_with_parent(outdir)
    try:
        written = render(a.results, outdir, a.channel, a.balance, a.compare, a.tables)
    except PlotError as e:
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 1
    for w in written:
        print(w)
    return 0
