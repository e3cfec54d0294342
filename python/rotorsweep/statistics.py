"""Statistics and Sobol' indices of a sampled study (a study with ``[sample]``), as pandas.

>>> import rotorsweep as rs
>>> st = rs.statistics("sens.h5")      # one row per output: mean, std, quantiles, their 95 % CIs
>>> si = rs.sensitivity("sens.h5")     # one row per output and parameter: first_order, total, CIs
>>> sa = rs.samples("sens.h5")         # one row per job: its sampled inputs and its outputs

In: a results file of ``rotorsweep run`` on a sampled study. Out: the ``statistics`` and
``sensitivity`` tables of ``rotorsweep report FILE --table NAME --format json`` (docs/statistics.md)
as DataFrames, one column per table column, numbers as float (a missing value NaN), ``n`` as int
(of a study with grid axes, one block of rows per grid point, led by a column per swept key: its
value as float, or as text for a key of text values);
``df.attrs["title"]`` and ``df.attrs["legend"]`` say what the columns hold. The binary computes
them (one implementation of the estimators); it is found as :func:`rotorsweep.find_binary` does.
A file without the table (not a sampled study; ``sensitivity`` needs ``method = "saltelli"``)
raises :class:`rotorsweep.RotorsweepError` with the binary's message.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pandas as pd

from .runner import DEFAULT_TIMEOUT, PathLike, _find_binary, _invoke


def _table(path: PathLike, name: str, timeout: float | None, binary: PathLike | None) -> pd.DataFrame:
    p = _invoke(
        _find_binary(binary),
        ["report", str(path), "--table", name, "--format", "json"],
        timeout=timeout,
    )
    doc: dict[str, Any] = json.loads(p.stdout)
    table = doc["tables"][0]
    df = pd.DataFrame(table["rows"], columns=table["columns"])
    for c in df.columns:
        if c == "n":
            df[c] = df[c].astype("int64")
        elif c in ("output", "parameter", "job_id", "label"):
            df[c] = df[c].astype(str)
        else:
            try:
                df[c] = df[c].astype(float).fillna(np.nan)
            except (TypeError, ValueError):  # a swept key of text values
                df[c] = df[c].astype(str)
    df.attrs["title"] = table["title"]
    df.attrs["legend"] = table["legend"]
    return df


def statistics(
    path: PathLike, *, timeout: float | None = DEFAULT_TIMEOUT, binary: PathLike | None = None
) -> pd.DataFrame:
    """Per output of the sampled study in ``path``: ``output``, ``n``, ``mean``, ``std``, ``q05``,
    ``q50``, ``q95`` each with ``_low`` and ``_high`` (95 % bootstrap interval), ``min``, ``max``
    (the output's unit is in its name)."""
    return _table(path, "statistics", timeout, binary)


def samples(
    path: PathLike, *, timeout: float | None = DEFAULT_TIMEOUT, binary: PathLike | None = None
) -> pd.DataFrame:
    """Per job of the sampled study in ``path`` that ended ok: ``job_id``, ``label`` (its design
    row), each sampled parameter's value (column: its first key) and each output (its unit in
    its name; NaN where the job has none)."""
    return _table(path, "samples", timeout, binary)


def sensitivity(
    path: PathLike, *, timeout: float | None = DEFAULT_TIMEOUT, binary: PathLike | None = None
) -> pd.DataFrame:
    """Per output and sampled parameter of the Saltelli study in ``path``: ``output``,
    ``parameter``, ``n`` (design rows used), ``first_order`` and ``total`` Sobol' indices each
    with ``_low`` and ``_high`` (95 % bootstrap interval); of a Morris study ``mu``, ``mu_star``
    and ``sigma`` of the elementary effects instead, each with ``_low`` and ``_high``."""
    return _table(path, "sensitivity", timeout, binary)
