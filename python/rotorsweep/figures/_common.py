"""What every figure family shares: the error type, the canvas, the constants of the layout and
the panels' grid, the input file's kind, the jobs' setting text and measured numbers as text
(:func:`significant`, the report's rule)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import h5py
import numpy as np
import pandas as pd

from rotorsweep import PathLike

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: The channel drawn when none is asked for (``--channel``).
DEFAULT_CHANNEL = "centre/vertical"
#: Resolution of the PNG files [dots per inch].
DPI = 110
#: Directions of the runout channels, in panel order.
DIRECTIONS = ("vertical", "horizontal")
#: Decades of amplitude below the map's maximum that the colour scales of the maps span.
MAP_DECADES = 4
#: Statuses of a run that reached its end time (its records are complete).
COMPLETED = ("ok", "untrusted")
#: Most sensors drawn in the Bode, polar and order-Bode figures (one column or polar axes each).
MAX_SENSORS = 4

#: The text of each number a figure writes (value → text, :class:`~.tables.NumberTexts`).
Numbers = Mapping[float, str]


class PlotError(Exception):
    """The file is not a results file the figures read, a requested channel is not in it, or the
    report's tables (``--tables``, or the binary that prints them) are missing or unfit."""


def figure(**kw: object) -> "Figure":
    """A figure with constrained layout on an Agg canvas of its own (matplotlib's global backend
    is left alone). matplotlib is imported here, at the first figure: this module, the error
    type and :mod:`.tables` need none."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(layout="constrained", **kw)
    FigureCanvasAgg(fig)
    return fig


def grid(n: int, most: int = 3) -> tuple[int, int]:
    """The rows and columns of a grid of ``n`` panels, at most ``most`` a row."""
    cols = min(n, most)
    return -(-n // cols), cols


def save(fig: "Figure", path: Path) -> Path:
    """Writes ``fig`` as a PNG of :data:`DPI` to ``path``; returns ``path``."""
    fig.savefig(path, dpi=DPI)
    return path


def file_kind(path: PathLike) -> str:
    """What the results file ``path`` is, read once: ``"calibration"`` (root attribute ``kind =
    "calibration"`` and a ``/calibration`` group, ``rotorsweep calibrate -o``), ``"study"``
    (tool attribute "rotorsweep" and a ``/summary`` table, ``rotorsweep run`` or ``merge``) or
    ``"linear"`` (a ``/linear`` group, ``rotorsweep linear -o``) or ``"barring"`` (a ``/barring``
    group, ``rotorsweep barring -o``); :class:`PlotError` naming
    ``path`` when it is missing, not HDF5 or none of these."""
    if not Path(path).is_file():
        raise PlotError(f"{path}: no such file")
    try:
        with h5py.File(path, "r") as f:
            calibration = f.attrs.get("kind") == "calibration" and "calibration" in f
            tool = f.attrs.get("tool")
            has_summary = "summary" in f
            has_linear = "linear" in f
            has_barring = "barring" in f
    except OSError as e:
        raise PlotError(f"{path}: not an HDF5 file ({e})") from None
    if calibration:
        return "calibration"
    if tool == "rotorsweep" and has_barring and not (has_summary or has_linear):
        return "barring"
    if tool != "rotorsweep" or not (has_summary or has_linear):
        raise _not_results(path)
    return "study" if has_summary else "linear"


def _not_results(path: PathLike) -> PlotError:
    return PlotError(
        f"{path}: not a rotorsweep study results file (no /summary table; "
        "`rotorsweep run STUDY -o OUT.h5` writes one), a `rotorsweep linear -o` file "
        "(no /linear group), a `rotorsweep barring -o` file (no /barring group) nor a "
        "`rotorsweep calibrate -o` file (no kind = calibration)"
    )


def check_results_file(path: PathLike) -> bool:
    """Raises :class:`PlotError` naming ``path`` unless it is an HDF5 file written by
    ``rotorsweep run`` or ``merge`` (tool attribute "rotorsweep" and a ``/summary`` table) or by
    ``rotorsweep linear -o`` (a ``/linear`` group); True for a study results file."""
    kind = file_kind(path)
    if kind == "calibration":
        raise _not_results(path)
    return kind == "study"


def settings(summary: pd.DataFrame, labels: pd.DataFrame, keys: list[str],
             numbers: Numbers) -> pd.Series:
    """A short text per job (index job_id, summary order) naming its values of the varying
    ``keys``: the label of each labelled axis among them (``labels`` as
    :func:`rotorsweep.job_labels` returns it), then ``key=value`` for every key that no shown
    label determines (a key is determined by a label when all jobs with that label share its
    value, as the other keys of a zipped axis do); a number's text is ``numbers[value]`` (the
    report's, :mod:`.tables`). "" for every job when nothing is left."""
    df = summary.set_index("job_id")
    shown = [k for k in labels.columns if k in keys]
    parts = [labels.loc[df.index, k].fillna("").astype(str) for k in shown]
    by_label = [df.groupby(p.to_numpy()) for p in parts]

    def text(value: object) -> str:
        return numbers[value] if isinstance(value, float) else str(value)

    for k in keys:
        if not any(g[k].nunique(dropna=False).max() <= 1 for g in by_label):
            parts.append(k + "=" + df[k].map(text))
    if not parts:
        return pd.Series("", index=df.index)
    return pd.concat(parts, axis=1).agg(lambda row: ", ".join(p for p in row if p), axis=1)


def significant(x: float, sig: int) -> str:
    """A measured value to ``sig`` significant digits as the report writes it (Rust's
    ``text::significant``): scientific below 1e-3 and from 1e6 (``1.23e-4``, ``2.50e7``: no
    ``+`` and no leading zeros in the exponent), fixed-point between; "–" for no value, "0" for
    zero."""
    x = float(x)
    if not np.isfinite(x):
        return "–"
    if x == 0.0:
        return "0"
    mag = int(np.floor(np.log10(abs(x))))
    if not -3 <= mag < 6:
        mantissa, _, exponent = f"{x:.{sig - 1}e}".partition("e")
        return f"{mantissa}e{int(exponent)}"
    return f"{x:.{max(sig - 1 - mag, 0)}f}"


def unwrap_deg(phase: np.ndarray) -> np.ndarray:
    """Unwrapped phase [°], NaN kept in place."""
    out = np.full(phase.shape, np.nan)
    ok = np.isfinite(phase)
    out[ok] = np.degrees(np.unwrap(np.radians(phase[ok])))
    return out
