"""The comparison of a measured record (``rotorsweep import``) with the model's simulated run-up,
one ramp job each, as ``rotorsweep report MEASURED --compare SIMULATED``: their waterfalls side
by side (amplitude [µm] over frequency [Hz] and speed [Hz]) and their tracked order amplitudes
[µm] over speed [Hz]."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pandas as pd
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure
from matplotlib.patches import Patch

import rotorsweep as rp
from rotorsweep import PathLike

from ._common import DIRECTIONS, MAP_DECADES, Numbers, PlotError, figure
from .ramps import ramp_jobs, waterfall_data

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
    fig = figure(figsize=(11.5, 4.6 * len(dirs) + 0.8))
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
                   title: str, numbers: Numbers) -> Figure | None:
    """The tracked order amplitudes [µm, log] of ``sensor`` over speed [Hz] in block (time) order
    (a measured record's block speeds scatter with its keyphasor's timing), measured (solid,
    dots) and simulated (dashed) in one colour per order tracked in both (named as ``numbers``
    writes it), a panel per direction. None when the two share no order of that sensor."""
    dirs = [d for d in DIRECTIONS
            if not measured[(measured["sensor"] == sensor) & (measured["direction"] == d)].empty]
    shared = sorted(set(measured["order"]) & set(simulated["order"]))
    if not dirs or not shared:
        return None
    fig = figure(figsize=(5.6 * len(dirs) + 0.8, 5.4))
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
    handles = [Patch(color=f"C{i}", label=f"{numbers[k]}×")
               for i, k in enumerate(shared)]
    handles += [axes[0].plot([], [], color="k", ls="-", marker=".", label="measured")[0],
                axes[0].plot([], [], color="k", ls="--", label="simulated")[0]]
    axes[0].legend(handles=handles, fontsize="small")
    fig.suptitle(f"{title}: tracked order amplitudes, measured vs simulated")
    return fig


def compare_figures(measured: PathLike, simulated: PathLike, sensor: str | None,
                    numbers: Numbers) -> list[tuple[str, Figure | None]]:
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
        out.append(("compare_orders.png", compare_orders(morders, sorders, which, title,
                                                               numbers)))
    return out
