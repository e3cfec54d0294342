"""The figures of a ramp job (a run-up or coast-down: a job whose speed changed while recording,
its ``/jobs/<id>/waterfall`` and ``/analysis/orders`` rows): the waterfall (amplitude [µm] over
frequency [Hz] and block time [s]), the order map (tracked order amplitudes [µm] over speed
[Hz]) and the order-tracked Bode plot (1× amplitude [µm] and phase [°] over speed [Hz])."""

from __future__ import annotations

import re

import h5py
import numpy as np
import pandas as pd
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure

import rotorsweep as rp
from rotorsweep import PathLike

from ._common import DIRECTIONS, MAP_DECADES, MAX_SENSORS, Numbers, figure, unwrap_deg
from .linear import linear_groups, mark_criticals, responses

#: Colours of the runout directions in the order figures (as in the Bode plots).
DIRECTION_COLOURS = {"vertical": "tab:orange", "horizontal": "tab:blue"}
#: What the order Bode plot's curves contain, as their legends say: the run's tracked 1× holds
#: every once-per-revolution source the scene has (the unbalance's response, the journals' and
#: rollers' roundness it runs on, and the shell's own out-of-roundness that the sensor reads
#: whatever the speed), the linear steady state the unbalance's response alone.
TRACKED = "tracked 1×, all sources (unbalance, journal roundness, shell shape)"
STEADY_STATE = "steady state, unbalance only (linear)"


def ramp_jobs(path: PathLike) -> list[str]:
    """The jobs with a waterfall (``/jobs/<id>/waterfall``: speed changed while recording), in
    job-index order."""
    with h5py.File(path, "r") as f:
        return [i for i in rp.job_ids(path) if f"jobs/{i}/waterfall/freq_hz" in f]


def waterfall_data(path: PathLike, job: str) -> dict[str, np.ndarray]:
    """A ramp job's waterfall (the run's order tracking): ``time_s`` and ``speed_hz`` [blocks],
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
              name: str, numbers: Numbers) -> Figure | None:
    """A ramp's waterfall of ``sensor``: the amplitude [µm, log colour scale spanning
    :data:`MAP_DECADES`] of Hanning spectra of half-overlapping time blocks over frequency [Hz]
    (rows: the blocks' mid time [s], the right axis their mean speed [Hz]), one panel per
    direction, with the order lines f = k·speed(t) of the tracked ``orders`` (labelled as
    ``numbers`` writes them); None without a map of that sensor or when it is zero."""
    dirs = [d for d in DIRECTIONS if f"map/{sensor}/{d}" in data]
    if not dirs or len(data["time_s"]) < 2:
        return None
    maps = [data[f"map/{sensor}/{d}"] for d in dirs]
    top = max(np.max(m, initial=0.0) for m in maps)
    if not top > 0:
        return None
    t, speed, freq = data["time_s"], data["speed_hz"], data["freq_hz"]
    norm = LogNorm(vmin=top / 10**MAP_DECADES, vmax=top, clip=True)
    fig = figure(figsize=(5.6 * len(dirs) + 1.4, 6.2))
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
                ax.text(k * speed[i], t[i], f"{numbers[k]}×", color="white",
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


def order_map(orders: pd.DataFrame, job: str, sensor: str, study: str, name: str,
              numbers: Numbers) -> Figure | None:
    """A ramp's order map of ``sensor``: the tracked amplitude [µm, log] of each order over the
    blocks' mean speed [Hz], one line per order (named as ``numbers`` writes it), one panel per
    direction; the order resonances
    of ``/analysis/order_resonances`` are the curves' peaks. None without tracked rows of that
    sensor."""
    dirs = [d for d in DIRECTIONS if not _job_orders(orders, job, sensor, d).empty]
    if not dirs:
        return None
    fig = figure(figsize=(5.4 * len(dirs) + 0.8, 5.2))
    axes = fig.subplots(1, len(dirs), sharey=True, squeeze=False)[0]
    for ax, d in zip(axes, dirs):
        rows = _job_orders(orders, job, sensor, d)
        for i, (k, g) in enumerate(rows.groupby("order", sort=True)):
            amp = g["amplitude_um"].to_numpy()
            ax.plot(g["speed_hz"], np.where(amp > 0, amp, np.nan), color=f"C{i}",
                    marker=".", ms=2, lw=1, label=f"{numbers[k]}×")
        ax.set_yscale("log")
        ax.set_title(f"{sensor} {d}")
        ax.set_xlabel("speed, block mean [Hz]")
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel("order amplitude [µm]")
    axes[0].legend(title="order", fontsize="small")
    fig.suptitle(_job_title(study, "order map (tracked order amplitudes)", name))
    return fig


def _lowest_speed_phase(speed: np.ndarray, phase: np.ndarray) -> float:
    """The phase [°] at the lowest speed that has one (0 when none has)."""
    ok = np.flatnonzero(np.isfinite(phase))
    return float(phase[ok[np.argmin(speed[ok])]]) if ok.size else 0.0


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
    it, and the critical speeds dotted; without, each block's phase moved by whole turns into
    the window from 90° above to 270° below the phase at the lowest speed. Steps over 180° are
    not joined.
    The legend says what each curve holds (:data:`TRACKED`, :data:`STEADY_STATE`): where they
    part away from the resonance, the difference is the run's other 1× sources (a journal's
    roundness reads at 1× at every speed). None without tracked 1× rows."""
    one = orders[orders["job_id"].eq(job) & np.isclose(orders["order"], 1.0)]
    sensors = list(dict.fromkeys(one["sensor"]))[:MAX_SENSORS]
    if not sensors:
        return None
    have_linear = linear is not None and bool(responses(linear))
    fig = figure(figsize=(max(4.6 * len(sensors) + 0.6, 7.0), 7.4))
    axes = fig.subplots(2, len(sensors), sharex=True, squeeze=False)
    for c, sensor in enumerate(sensors):
        for d in DIRECTIONS:
            rows = _job_orders(one, job, sensor, d)
            if rows.empty:
                continue
            colour = DIRECTION_COLOURS[d]
            speed = rows["speed_hz"].to_numpy()
            phase = unwrap_deg(rows["phase_deg"].to_numpy())
            key = f"unbalance_response/{sensor}/{d}"
            if have_linear and f"{key}/amplitude_um" in linear:
                lin_speed = np.asarray(linear["campbell/speed_hz"])
                lin_amp = np.asarray(linear[f"{key}/amplitude_um"])
                lin_phase = unwrap_deg(
                    np.where(lin_amp > 0, np.asarray(linear[f"{key}/phase_deg"]), np.nan))
                axes[0, c].plot(lin_speed, lin_amp, color=colour, ls="--", lw=1,
                                label=f"{d}, {STEADY_STATE}")
                axes[1, c].plot(lin_speed, lin_phase, color=colour, ls="--", lw=1)
                # Each block's phase by whole turns nearest the steady state's at its speed.
                ref = np.interp(speed, lin_speed, lin_phase)
                phase = np.where(np.isfinite(ref), phase + 360.0 * np.round((ref - phase) / 360.0),
                                 phase)
            else:
                # Each block's phase by whole turns into the window from 90° above to 270° below
                # the phase at the lowest speed (in (−180°, 180°]): the lag a critical adds stays
                # inside, and a phase near the window's edge does not flicker by a turn. Not
                # unwrapped along the blocks: the free vibration beating with the 1× past a
                # critical (the tracked phasor circling the origin) adds a turn per beat,
                # thousands of degrees that would read as a phase change of the response.
                top = 90.0 - np.mod(180.0 - _lowest_speed_phase(speed, phase), 360.0) + 180.0
                phase = top - np.mod(top - phase, 360.0)
            axes[0, c].plot(speed, rows["amplitude_um"], color=colour, lw=1.3,
                            label=f"{d}, {TRACKED}")
            axes[1, c].plot(*_break_jumps(speed, phase), color=colour, lw=1.0, marker=".", ms=2)
        axes[0, c].set_title(sensor)
        axes[1, c].set_xlabel("speed, block mean [Hz]")
        for ax in axes[:, c]:
            if have_linear:
                mark_criticals(ax, linear)
            ax.grid(alpha=0.3)
    for ax in axes[0]:
        ax.set_yscale("log")
    axes[0, 0].set_ylabel("1× amplitude [µm], log")
    axes[1, 0].set_ylabel("1× phase [°] (x = A cos(θ + φ))")
    if have_linear:
        axes[0, 0].plot([], [], color="tab:red", lw=0.8, ls=":", label="critical speeds")
    # Below the panels, where the long labels that say what each curve holds cover no curve.
    fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="outside lower center",
               ncols=1 if len(sensors) == 1 else 2, fontsize="small")
    what = "order-tracked 1× (Bode)" + (
        " and the unbalance's steady state" if have_linear else "")
    fig.suptitle(_job_title(study, what, name))
    return fig


def file_suffixes(jobs: list[str], names: pd.Series) -> dict[str, str]:
    """The file-name suffix of each of ``jobs``: "" for one job; for several, the job's setting
    (``names``: the study's axis labels, ``key=value`` of the other varying keys) as a file name
    — lower case, each run of characters other than letters, digits, ``.`` and ``_`` one ``-``
    ("run-up 0.1 Hz/s" → ``-run-up-0.1-hz-s``) — or the job id where settings are missing or
    two jobs' would be the same name."""
    if len(jobs) < 2:
        return {j: "" for j in jobs}
    slugs = {j: re.sub(r"[^a-z0-9._]+", "-", str(names.get(j, "")).lower()).strip("-")
             for j in jobs}
    if all(slugs.values()) and len(set(slugs.values())) == len(jobs):
        return {j: f"-{slugs[j]}" for j in jobs}
    return {j: f"-{j}" for j in jobs}


def ramp_figures(path: PathLike, orders: pd.DataFrame, sensor: str | None, names: pd.Series,
                 study: str, numbers: Numbers) -> list[tuple[str, Figure | None]]:
    """Per ramp job (:func:`ramp_jobs`) its waterfall, order map and order Bode plot, named
    ``waterfall[-<setting>].png``, ``order_map[-<setting>].png``, ``order_bode[-<setting>].png``
    (the suffix only with several ramp jobs: :func:`file_suffixes`, the job's setting by the
    study's axis labels), titled by the job's setting ``names``; ``orders`` is the
    ``/analysis/orders`` table. The waterfall and order map draw ``sensor``; None: "centre"
    where the job has it, else its first sensor."""
    jobs = ramp_jobs(path)
    if not jobs:
        return []
    suffixes = file_suffixes(jobs, names)
    attrs = rp.job_attrs(path)
    systems = linear_groups(path)
    out: list[tuple[str, Figure | None]] = []
    for job in jobs:
        suffix = suffixes[job]
        name = str(names.get(job, job))
        tracked = sorted(set(orders.loc[orders["job_id"] == job, "order"])) if not orders.empty \
            else []
        data = waterfall_data(path, job)
        sensors = list(dict.fromkeys(k.split("/")[1] for k in data if k.startswith("map/")))
        which = sensor or ("centre" if "centre" in sensors or not sensors else sensors[0])
        out.append((f"waterfall{suffix}.png", waterfall(data, which, tracked, study, name,
                                                        numbers)))
        if orders.empty:
            continue
        linear_id = attrs.at[job, "linear_id"] if "linear_id" in attrs else None
        linear = systems.get(linear_id) if isinstance(linear_id, str) else None
        out.append((f"order_map{suffix}.png", order_map(orders, job, which, study, name,
                                                        numbers)))
        out.append((f"order_bode{suffix}.png", order_bode(orders, job, linear, study, name)))
    return out
