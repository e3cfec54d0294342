"""The balancing figure: the 1× amplitude [µm] per sensor and direction before the corrections,
as the influence coefficients predict it after them and, with ``--check``, in the check run,
from the JSON of ``rotorsweep balance OUT.h5 --json [--check]`` (speeds [Hz], masses [g], angles
[°], planes z [mm])."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from rotorsweep import PathLike

from ._common import Numbers, PlotError, figure

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


def balancing(data: dict[str, object], study: str, numbers: Numbers) -> Figure:
    """Balancing before and after per sensor: bars of the 1× amplitude [µm, log] at each sensor
    and direction, one panel per speed: the reference run (before), the influence coefficients'
    prediction after the corrections and, when ``data`` has ``check``, the check run of the
    corrected roll with its reduction [%]; the corrections in the title, the speeds as
    ``numbers`` writes them."""
    pred = pd.DataFrame(data["predicted"])
    check = pd.DataFrame(data.get("check") or [])
    speeds = sorted(pred["speed_hz"].unique())
    fig = figure(figsize=(max(4.2 * len(speeds) + 0.8, 7.0), 5.4))
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
        ax.set_title(f"{numbers[speed]} Hz")
        ax.grid(alpha=0.3, axis="y", which="both")
    axes[0].set_ylabel("1× runout amplitude [µm], log")
    axes[0].legend(fontsize="small")
    masses = "; ".join(f"z {float(c['z_mm']):g} mm: {float(c['mass_g']):.0f} g at "
                       f"{float(c['angle_deg']):.1f}°" for c in data["corrections"])
    fig.suptitle(f"{study}: balancing before and after\ncorrections {masses}",
                 fontsize="medium")
    return fig
