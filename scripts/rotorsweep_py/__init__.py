"""rotorsweep_py: read rotorsweep's HDF5 results (see :mod:`rotorsweep_py.loader`).

>>> from rotorsweep_py import load_summary, channel
>>> df = load_summary("smoke.h5")                      # one row per job
>>> t, x, units = channel("smoke.h5", df.job_id[0], "runout/centre/vertical")
"""

from .loader import (
    COUNT_COLUMNS,
    RUN_GROUPS,
    Job,
    Model,
    Sweep,
    analysis_table,
    channel,
    channels,
    file_attrs,
    job_attrs,
    job_ids,
    job_labels,
    load_job,
    load_summary,
    models,
    sweeps,
    varying_keys,
)

__all__ = [
    "COUNT_COLUMNS",
    "RUN_GROUPS",
    "Job",
    "Model",
    "Sweep",
    "analysis_table",
    "channel",
    "channels",
    "file_attrs",
    "job_attrs",
    "job_ids",
    "job_labels",
    "load_job",
    "load_summary",
    "models",
    "sweeps",
    "varying_keys",
]
__version__ = "0.1.0"
