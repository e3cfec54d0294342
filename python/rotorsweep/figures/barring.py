"""The barring stability map of a machine's viscoelastic nip, from the file ``rotorsweep barring
MACHINE -o MAP.h5`` writes (``src/results/barring_file.rs``; Rust computes the roots, this
module only draws them).

In: the group ``barring/<nip>`` of that file: the axes ``speeds_hz`` [Hz] (the first roll's) and
``loads_kn_per_m`` [kN/m], the [loads × speeds] datasets ``growth_per_s`` [1/s] (the rightmost
root the nip takes part in), ``frequency_hz`` [Hz], ``polygon_order`` and ``stable``, per load
``onset_speed_hz`` [Hz] (NaN: stable over the grid) and ``onset_polygon_order``; the group's
attributes ``covered_roll`` and ``cover_speed_per_speed``.

Out: :func:`barring_map` (``barring_map.png``), per nip a row of two panels: left, the growth
rate over speed, a line per load, the unstable points filled and labelled with their polygon
order (the number of sides the cover's barring pattern has), each load's onset a dashed
vertical line; right, the stability chart over speed × load, each cell coloured by its growth
rate (diverging about 0: red grows, blue decays), the unstable cells labelled with their
polygon order, and the root's frequency [Hz] over speed below, a line per load.
"""

from __future__ import annotations

import h5py
import numpy as np
from matplotlib.colors import TwoSlopeNorm
from matplotlib.figure import Figure

from rotorsweep import PathLike

from ._common import figure

#: Most nips drawn (a row each).
MAX_NIPS = 4


def _read(path: PathLike) -> list[dict]:
    """Every nip's map of the file as numpy arrays, in the file's order."""
    out = []
    with h5py.File(path, "r") as f:
        for nip, g in f["barring"].items():
            out.append({
                "nip": nip,
                "covered_roll": str(g.attrs.get("covered_roll", "")),
                "cover_per_speed": float(g.attrs.get("cover_speed_per_speed", np.nan)),
                "speeds": g["speeds_hz"][()],
                "loads": g["loads_kn_per_m"][()],
                "growth": g["growth_per_s"][()],
                "freq": g["frequency_hz"][()],
                "order": g["polygon_order"][()],
                "stable": g["stable"][()] > 0.5,
                "onset": g["onset_speed_hz"][()],
                "onset_order": g["onset_polygon_order"][()],
            })
    return out


def _edges(x: np.ndarray) -> np.ndarray:
    """Cell edges about the centres ``x`` (ascending), half a step beyond the ends."""
    if len(x) == 1:
        return np.array([x[0] - 0.5, x[0] + 0.5])
    mid = 0.5 * (x[1:] + x[:-1])
    return np.concatenate([[2 * x[0] - mid[0]], mid, [2 * x[-1] - mid[-1]]])


def barring_map(path: PathLike, title: str) -> Figure:
    """The barring map figure of the file ``path`` (module doc), ``title`` its heading."""
    maps = _read(path)
    shown = maps[:MAX_NIPS]
    fig = figure(figsize=(13.0, 6.2 * len(shown)))
    rows = fig.subfigures(len(shown), 1, squeeze=False)[:, 0]
    for sub, m in zip(rows, shown):
        left, right = sub.subplots(1, 2, width_ratios=[1.1, 1.0])
        speeds, loads = m["speeds"], m["loads"]
        for i, load in enumerate(loads):
            colour = f"C{i}"
            g, unstable = m["growth"][i], ~m["stable"][i]
            left.plot(speeds, g, "-", color=colour, lw=1.2, label=f"{load:g} kN/m")
            left.plot(speeds[~unstable], g[~unstable], "o", ms=3, color=colour,
                      markerfacecolor="white")
            left.plot(speeds[unstable], g[unstable], "o", ms=5, color=colour)
            for s, y, n in zip(speeds[unstable], g[unstable], m["order"][i][unstable]):
                left.annotate(f"{int(n)}", (s, y), textcoords="offset points", xytext=(0, 5),
                              ha="center", fontsize=7, color=colour)
            if np.isfinite(m["onset"][i]):
                left.axvline(m["onset"][i], color=colour, ls="--", lw=0.8)
        left.axhline(0.0, color="k", lw=0.8)
        left.set_xlabel("first roll's speed [Hz]")
        left.set_ylabel("growth rate of the rightmost barring root [1/s]")
        left.grid(True, alpha=0.3)
        left.legend(title="line load (filled: unstable,\nlabel: polygon order; dashed: onset)",
                    fontsize=8, title_fontsize=8, loc="best")
        left.set_title(f"nip {m['nip']}: growth over speed", fontsize=10)

        ax = right
        growth = m["growth"]
        span = float(np.nanmax(np.abs(growth))) if np.isfinite(growth).any() else 1.0
        norm = TwoSlopeNorm(vcenter=0.0, vmin=-span, vmax=span)
        order = np.argsort(loads)
        mesh = ax.pcolormesh(_edges(speeds), np.arange(len(loads) + 1) - 0.5,
                             growth[order], cmap="RdBu_r", norm=norm, shading="flat")
        for r, i in enumerate(order):
            for s, n, st in zip(speeds, m["order"][i], m["stable"][i]):
                if not st:
                    ax.text(s, r, f"{int(n)}", ha="center", va="center", fontsize=6)
        ax.set_yticks(np.arange(len(loads)), [f"{loads[i]:g}" for i in order])
        ax.set_ylabel("line load [kN/m]")
        ax.set_xlabel("first roll's speed [Hz]")
        ax.set_title("stability chart (numbers: polygon order of the unstable points)",
                     fontsize=10)
        sub.colorbar(mesh, ax=ax, label="growth rate [1/s]")
        onsets = [f"{loads[i]:g} kN/m: {m['onset'][i]:g} Hz, {int(m['onset_order'][i])} sides"
                  if np.isfinite(m["onset"][i]) else f"{loads[i]:g} kN/m: stable"
                  for i in range(len(loads))]
        sub.suptitle(f"{title}: barring of nip {m['nip']} (cover on {m['covered_roll']}, "
                     f"turning at {m['cover_per_speed']:.4f} × the first roll's speed)\n"
                     f"onset {'; '.join(onsets)}", fontsize=10)
    return fig


def barring_frequency(path: PathLike, title: str) -> Figure:
    """The frequency [Hz] of each point's rightmost barring root over speed, a line per load and
    nip, the unstable points filled (``barring_frequency.png``)."""
    maps = _read(path)[:MAX_NIPS]
    fig = figure(figsize=(8.0, 4.5))
    ax = fig.subplots()
    for k, m in enumerate(maps):
        for i, load in enumerate(m["loads"]):
            colour = f"C{(k * len(m['loads']) + i) % 10}"
            f, unstable = m["freq"][i], ~m["stable"][i]
            name = f"{m['nip']}, {load:g} kN/m" if len(maps) > 1 else f"{load:g} kN/m"
            ax.plot(m["speeds"], f, "-", color=colour, lw=0.8, label=name)
            ax.plot(m["speeds"][unstable], f[unstable], "o", ms=5, color=colour)
            ax.plot(m["speeds"][~unstable], f[~unstable], "o", ms=3, color=colour,
                    markerfacecolor="white")
    ax.set_xlabel("first roll's speed [Hz]")
    ax.set_ylabel("frequency of the rightmost barring root [Hz]")
    ax.grid(True, alpha=0.3)
    ax.legend(title="filled: unstable", fontsize=8, title_fontsize=8, loc="center left",
              bbox_to_anchor=(1.02, 0.5))
    ax.set_title(f"{title}: barring frequency", fontsize=10)
    return fig
