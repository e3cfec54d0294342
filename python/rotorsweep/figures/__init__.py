"""PNG figures of a rotorsweep results file.

In: an HDF5 results file of ``rotorsweep run`` or ``merge`` (a study), of ``rotorsweep
simulate -o`` (laid out as a study of one job), of ``rotorsweep linear -o`` (linearised
systems), of ``rotorsweep calibrate -o`` (a calibration) or of ``rotorsweep barring -o`` (a
barring map: ``barring_map.png`` and ``barring_frequency.png`` only, :mod:`.barring`); optionally the JSON of ``rotorsweep balance FILE --json [--check]`` (``--balance``), a
simulated results file to compare a measured record with (``--compare``), and the JSON of
``rotorsweep report FILE --format json`` (``--tables``: the error classes and the text of the
numbers the labels write, below).
Out: PNG files (110 dpi) in a folder (``-o DIR``, default ``FILE-plots`` beside the file), each
only when the file holds its data, and their paths on standard output, one a line, in the order
below (the Rust report reads them in that order).
Units: frequencies and speeds [Hz], runout amplitudes and errors [µm], phases and angles [°],
CPU time [s], time [s], axial positions z [mm], support stiffness [N/m], masses [g].

    python -m rotorsweep.figures FILE.h5 [-o DIR] [--channel SENSOR/DIR] [--balance JSON]
                                 [--compare SIMULATED.h5] [--tables TABLES.json]
    python3 scripts/plots.py FILE.h5 …   (the same, from a checkout without installing)

Needs matplotlib: ``pip install "./python[figures]"``. ``import rotorsweep`` and ``import
rotorsweep.figures`` import no matplotlib; the figure modules do, at their first use.

Per speed sweep of a study (``/analysis/sweeps/<n>``; suffix ``-<n>`` only with several sweeps),
module :mod:`.sweeps`:

* ``spectral_map[-<n>].png``: the amplitude of the runout's fluctuating part (the mean, static
  sag, removed before the FFT) [µm, log colour scale] over frequency [Hz] × speed [Hz] up to the
  study's range (from its orders), one panel per direction of the chosen sensor, with the roll's
  lines f = k·speed (the study's integer orders k) and, dashed, the rollers' lines f = r·k·speed
  with r the scene's journal/roller diameter ratio (the jobs' ``roller_ratio:…`` attributes;
  none where the roller roundness follows the roll angle, r = 1);
* ``harmonics[-<n>].png``: the amplitude of each of the study's orders over speed (log), one
  panel per direction of the chosen sensor;
* ``mean[-<n>].png``: the mean runout (static sag and offset) [µm] over speed at each sensor, one
  panel per direction.

Then, per study (modules :mod:`.sweeps`, :mod:`.jobs`, :mod:`.linear`):

* ``trial_mass.png``: the 1× amplitude change |A| − |A₀| and vector change |A − A₀| against the
  baseline jobs over speed (``/analysis/trial_mass``), one panel per sensor in the chosen
  direction, one pair of curves per trial setting;
* ``work_precision.png``: runout error against the reference [µm] over CPU time [s], log–log,
  one panel per physics (the varying keys that are not ``solver.*`` nor ``reduction.*``, i.e.
  per reference run), one colour and marker per integrator, every point labelled with its
  solver setting, each integrator's work-precision front a line (jobs that ended ok; the legend
  counts the failed ones); 12 panels a figure, more physics on ``work_precision-2.png``, …;
* ``timing.png``: CPU time [s] per job coloured by status, annotated with Newton iterations per
  step; vertical bars up to 12 jobs, one horizontal bar a job above (every job shown);
* ``stability.png``: when ``solver.integrator`` and other keys vary, a matrix integrator ×
  setting coloured by the report's error class (the decade of the max error, or the status of a
  job that did not end ok), with the status, error [µm] and CPU time [s] in the cells;
* ``campbell.png``: the Campbell diagram of each linearised system (``/linear/<id>``, at most
  four panels): damped whirl frequencies [Hz] over spin speed [Hz], one line per branch, each
  branch in range labelled at its right end with its plane at standstill (vertical /
  horizontal) and its whirl at the top speed (forward / backward), the lines f = k·speed
  (k = 1…4, 1× solid) and the critical speeds; where the file has the log decrements every mode
  a marker by whirl (▲ forward, ▼ backward, ● mixed) coloured by its log decrement, with a
  colour bar.

Per linear system (:mod:`.linear`), each when its group holds the data (``rotorsweep linear -o``
writes them, a study's ``/linear`` groups where its ``[linear]`` table asks), suffixed
``-<system>`` when several systems have one: ``mode_shapes.png`` (the lowest four lateral modes
at the lowest and the highest speed, ``linear -o --shapes``), ``bode.png`` and ``polar.png`` (the
1× unbalance response per sensor, amplitude [µm] and phase [°] over speed, critical speeds
dotted; amplitude at angle φ), ``critical_map.png`` (undamped critical speeds against the
support stiffness, the actual supports' marked), ``floquet.png`` (−ln max|μ| per revolution over
speed, < 0 unstable, the Floquet-unstable ranges shaded, the damped modes' threshold dashed).

Per ramp job (:mod:`.ramps`: a job whose speed changed while recording, its
``/jobs/<id>/waterfall``), suffixed when several jobs have one by the job's setting as a file
name (the study's axis labels: ``-run-up-0.5-hz-s``; ``-<job_id>`` where two would be the same),
titled by the job's setting: ``waterfall.png`` (Hanning spectra of half-overlapping time blocks [µm, log] over
frequency, a row per block at its mid time [s], the block's mean speed [Hz] on the right axis,
the tracked orders' lines f = k·speed(t)), ``order_map.png`` (the tracked amplitude of each
order, ``/analysis/orders``, over the blocks' mean speed), ``order_bode.png`` (the tracked 1×
amplitude and phase over speed per sensor; with the job's ``/linear/<linear_id>`` unbalance
response that steady state dashed over it and the critical speeds dotted; the legend says what
each curve holds: the run's 1× every 1× source, journal roundness included, the steady state
the unbalance alone).

Per sampled study (``[sample]``, :mod:`.sampled`, from the report's ``samples``, ``statistics``
and ``sensitivity`` tables): ``histograms.png`` (a histogram per output of the chosen channel or
of none, mean and 5 %/95 % quantiles marked), ``scatter.png`` (each output against each sampled
input; a random wall's realised statistics stand for its seed) and ``sensitivity.png`` (per
output the first-order and total Sobol' indices, or Morris's μ* and σ, with their 95 %
intervals); a sampled study gets these instead of ``timing.png`` and the per-ramp-job figures
below (a bar or a waterfall per sample would be hundreds).

Last, with ``--balance JSON`` (:mod:`.balance`): ``balancing.png``, the 1× amplitude [µm, log]
per sensor and direction, one panel per speed: the reference run, the influence coefficients'
prediction after the corrections and, with ``--check``, the check run with its reduction [%];
the corrections (plane z, mass, angle) in the title.

Of a calibration results file (``rotorsweep calibrate -o``, :mod:`.calibration`, from
:func:`rotorsweep.calibration`), only its own: ``calibration_rows.png`` (the rows of resonance,
frequency and output targets, a panel per kind of output, grouped by order: measured ± σ and the
model at the start and at the fit), ``calibration_resonances.png`` (each resonance table's
speed and amplitude as a point: measured ± σ, the model from the start to the fit),
``calibration_records.png`` (a record's rows, the real and
imaginary part of the complex order amplitude [µm] over the block's speed [Hz], a column per
channel and order), ``calibration_residuals.png`` (every row's √w (model − measured)/σ at the
start and at the fit), ``calibration_cost.png`` (the cost of every evaluation by role, the
accepted path, and the cost per iteration), ``calibration_parameters.png`` (each parameter's
value at every evaluation, the accepted path, its bounds and the fit ± standard error) and
``calibration_correlation.png`` (the fitted parameters' correlation matrix as a heat map with its
values, from two parameters on).

With ``--compare SIMULATED.h5`` instead (:mod:`.compare`; FILE a measured record of ``rotorsweep
import``, SIMULATED the model's run-up, one ramp job each, as ``rotorsweep report MEASURED
--compare SIMULATED``), only ``compare_waterfall.png`` (the two waterfalls side by side, a row per
direction, on one colour scale) and ``compare_orders.png`` (tracked order amplitudes [µm, log]
over speed, measured solid, simulated dashed).

``--channel SENSOR/DIR`` picks the sensor of the maps, harmonics, waterfalls and order maps and
the direction of the trial-mass panels (default centre/vertical; a ramp job without a "centre"
sensor then shows its first sensor). Exit codes: 0 written (the paths printed), 1 an error (its
message on standard error, nothing written: the file is none of the above, has no such channel,
``--balance``/``--compare``/``--tables`` unfit, or no binary to ask for the tables), 2 a usage
error. Importable: :func:`render` does the same and returns the paths. Each figure is drawn on
an Agg canvas of its own; matplotlib's global backend is left alone.

**Numbers and error classes come from the Rust report, never from Python.** A job's error class
and the text of a number in a label (``key=value`` of a job's setting, an order "0.92×", a roller
ratio, a balancing speed) are written as ``rotorsweep report`` writes them, by reading them from
its JSON (:mod:`.tables` says exactly which fields): from ``--tables TABLES.json`` when given
(that JSON saved; the binary's ``report --format html`` passes its own), else by running
``rotorsweep report FILE --format json --labels`` once, when a figure first needs a value
(``$ROTORSWEEP_BIN``, else ``rotorsweep`` on PATH, else the checkout's
``target/release/rotorsweep`` or ``target/debug/rotorsweep``; an error saying what to install
when there is none). So the Rust ``number_text`` and ``error_class`` stay the one
implementation. Measured values a figure writes (the stability matrix's errors and CPU times,
a mode's log decrement) follow the same rule as the report's: ``_common.significant``, scientific
below 1e-3 and from 1e6, as Rust's ``text::significant``.
"""

from __future__ import annotations

import importlib

#: Public names and the module that defines each; imported at first use (PEP 562), so that
#: ``import rotorsweep.figures`` imports no matplotlib.
_EXPORTS = {
    "render": "run",
    "main": "run",
    "PlotError": "_common",
    "check_results_file": "_common",
    "settings": "_common",
    "ReportTables": "tables",
    "NumberTexts": "tables",
    "find_binary": "tables",
    "spectral_map": "sweeps",
    "roller_ratios": "sweeps",
    "sweep_means": "sweeps",
    "mean_runout": "sweeps",
    "harmonics": "sweeps",
    "trial_mass": "sweeps",
    "work_precision": "jobs",
    "timing": "jobs",
    "stability": "jobs",
    "linear_system": "linear",
    "linear_groups": "linear",
    "study_systems": "linear",
    "campbell": "linear",
    "mode_shapes": "linear",
    "bode": "linear",
    "polar": "linear",
    "critical_map": "linear",
    "floquet": "linear",
    "linear_figures": "linear",
    "ramp_jobs": "ramps",
    "waterfall_data": "ramps",
    "waterfall": "ramps",
    "order_map": "ramps",
    "order_bode": "ramps",
    "ramp_figures": "ramps",
    "read_balance": "balance",
    "balancing": "balance",
    "compare_waterfalls": "compare",
    "compare_orders": "compare",
    "compare_figures": "compare",
    "sampled_figures": "sampled",
    "histograms": "sampled",
    "scatter": "sampled",
    "sensitivity": "sampled",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> object:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
