"""A calibration's results (``rotorsweep calibrate CAL.toml -o OUT.h5``), as pandas.

>>> import rotorsweep as rs
>>> c = rs.calibration("table51.h5")
>>> c["parameters"][["name", "value", "std_error"]]    # fitted values and standard errors
>>> c["rows"][["output", "measured", "model", "residual"]]   # misfit per target row
>>> c["correlation"]                                    # indexed by parameter name

In: the results file of ``rotorsweep calibrate`` (layout in docs/calibration.md). Out: a dict of
``parameters`` (``name``, ``keys``, ``scale``, ``lower``, ``upper``, ``initial``, ``value``,
``std_error`` in the keys' units, ``at_bound``), ``rows`` (``target``, ``line``, ``output``,
``job``, ``measured``, ``std``, ``weight``, ``initial``, ``model``, ``residual``),
``correlation`` (parameters × parameters), ``covariance`` (the same, in the values' units),
``evaluations`` (one row per evaluated point: ``index``, ``role``, ``iteration``, ``batch``,
``job_ids``, ``ok``, ``cost``, then ``value:<parameter>`` and ``output:<target>``) and
``attrs`` (the root attributes: ``stop``, ``cost``, ``reduced_chi_square``, ``warnings``, …).
A file that is not a calibration raises :class:`rotorsweep.RotorsweepError`.
"""

from __future__ import annotations

from typing import Any

import h5py
import pandas as pd

from .results import _attrs, _table
from .runner import PathLike, RotorsweepError


def calibration(path: PathLike) -> dict[str, Any]:
    """The calibration in ``path`` (module doc)."""
    with h5py.File(path, "r") as f:
        attrs = _attrs(f)
        if attrs.get("kind") != "calibration" or "calibration" not in f:
            raise RotorsweepError(f"{path}: not a calibration results file (rotorsweep calibrate)")
        g = f["calibration"]
        parameters = _table(g["parameters"])
        rows = _table(g["rows"])
        names = list(parameters["name"])
        correlation = pd.DataFrame(g["correlation"][()], index=names, columns=names)
        covariance = pd.DataFrame(g["covariance"][()], index=names, columns=names)
        evaluations = _table(g["evaluations"])
        values = g["values"][()]
        outputs = g["outputs"][()]
    # One concat, not a column at a time (hundreds of record rows fragment the frame).
    extra = {f"value:{name}": values[:, k] if len(evaluations) else []
             for k, name in enumerate(names)}
    extra.update({f"output:{target}": outputs[:, i] if len(evaluations) else []
                  for i, target in enumerate(rows["target"])})
    evaluations = pd.concat([evaluations, pd.DataFrame(extra, index=evaluations.index)], axis=1)
    return {
        "parameters": parameters,
        "rows": rows,
        "correlation": correlation,
        "covariance": covariance,
        "evaluations": evaluations,
        "attrs": attrs,
    }
