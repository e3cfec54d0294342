"""The figures of a study's speed sweeps (``/analysis/sweeps/<n>``) and of its trial masses
(``/analysis/trial_mass``): spectral map, mean runout and order amplitudes over speed [Hz],
amplitudes in µm."""

from __future__ import annotations

import h5py
import numpy as np
import pandas as pd
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure

import rotorsweep as rp
from rotorsweep import PathLike

from ._common import DIRECTIONS, MAP_DECADES, Numbers, figure

#: Prefix of the job attributes that give each roller's line ratio (the study writes them).
ROLLER_RATIO = "roller_ratio:"


def _panels(data: dict[str, np.ndarray], sensor: str) -> list[str]:
    """The directions of ``sensor`` that ``data`` (a sweep's lines or maps) holds."""
    return [d for d in DIRECTIONS if f"{sensor}/{d}" in data]


def _sweep_title(study: str, what: str, sweep: rp.Sweep) -> str:
    return f"{study}: {what}" + (f"\n{sweep['fixed']}" if sweep["fixed"] else "")


def spectral_map(
    sweep: rp.Sweep,
    sensor: str,
    study: str,
    ratios: list[float] | None,
    ratio_texts: Numbers,
    mean_removed: bool = True,
) -> Figure | None:
    """The sweep's spectral map of ``sensor`` (amplitude [µm] of the fluctuating part over
    frequency [Hz] × speed [Hz], the stored range), one panel per direction on a shared log
    colour scale that spans :data:`MAP_DECADES` below the largest amplitude; white lines at the
    sweep's integer orders k·speed and, dashed, at r·k·speed for each roller ratio r in
    ``ratios`` (:func:`roller_ratios`; None: not known, no roller lines said), named in the
    title by their ``ratio_texts`` (the report's ``labels.roller_ratios``). A file written before
    the mean was removed (``mean_removed`` False) has it in the 0 Hz bin and the next one: those
    two are left out of the colour scale (clipped to its top). None when the sweep has no map of
    that sensor or it is zero."""
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
    fig = figure(figsize=(5.2 * len(dirs) + 1.2, 5.8))
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
        rollers = ", ".join(dict.fromkeys(ratio_texts[r] for r in ratios))
        what = f"spectral map (solid k·speed; dashed rollers' lines {rollers}·k·speed)"
    elif known:
        what = "spectral map (lines k·speed; the rollers' lines lie on them)"
    else:
        what = "spectral map (lines k·speed)"
    fig.suptitle(_sweep_title(study, what, sweep))
    return fig


def roller_ratios(attrs: pd.DataFrame, job_ids: list[str]) -> list[float] | None:
    """The distinct roller line ratios (``roller_ratio:<node>/<roller>`` attributes, ascending)
    of the jobs ``job_ids`` (``attrs`` as :func:`rotorsweep.job_attrs` gives them), as stored
    (ratios equal to 9 decimals count once); None in a file written before they were stored
    (unknown), [] for a scene without rollers."""
    cols = [c for c in attrs.columns if str(c).startswith(ROLLER_RATIO)]
    if not cols:
        return None
    values = attrs.loc[[j for j in job_ids if j in attrs.index], cols].to_numpy(dtype=float)
    distinct: dict[float, float] = {}
    for v in values[np.isfinite(values)]:
        distinct.setdefault(round(float(v), 9), float(v))
    return sorted(distinct.values())


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
    fig = figure(figsize=(5.0 * len(dirs) + 0.8, 4.2))
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


def harmonics(sweep: rp.Sweep, sensor: str, study: str, numbers: Numbers) -> Figure | None:
    """The amplitude [µm] of each of the sweep's orders over speed [Hz] at ``sensor``, log
    scale, one panel per direction (non-integer orders dashed; the legend's orders as
    ``numbers`` writes them); None when the sweep has no lines of that sensor."""
    dirs = _panels(sweep["lines"], sensor)
    if not dirs:
        return None
    fig = figure(figsize=(5.2 * len(dirs) + 0.8, 5))
    axes = fig.subplots(1, len(dirs), sharey=True, squeeze=False)[0]
    for ax, d in zip(axes, dirs):
        amp = sweep["lines"][f"{sensor}/{d}"]
        for k, order in enumerate(sweep["orders"]):
            style = "-" if float(order).is_integer() else "--"
            ax.plot(sweep["speed_hz"], amp[:, k], style, marker=".", label=f"{numbers[order]}×")
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
    fig = figure(figsize=(7.5, 2.4 * len(sensors) + 1))
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
