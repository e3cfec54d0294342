"""rotorsweep: read rotorsweep's HDF5 results as pandas and xarray (:mod:`rotorsweep.results`).

>>> import rotorsweep as rs
>>> df = rs.summary("smoke.h5")                       # one row per job, str text, units in attrs
>>> r = rs.runout("smoke.h5", df.job_id[0])           # xarray: vertical, horizontal over (sensor, time [s])
>>> s = rs.spectrum("smoke.h5", df.job_id[0])         # over (sensor, freq_hz [Hz])
>>> m = rs.spectral_map("smoke.h5", 0)                # over (sensor, speed_hz, freq_hz)
"""

from .results import (
    COUNT_COLUMNS,
    RUN_GROUPS,
    Job,
    JobRef,
    Model,
    PathLike,
    Sweep,
    analysis,
    analysis_table,
    campbell,
    channel,
    channels,
    contact_forces,
    file_attrs,
    job_attrs,
    job_id,
    job_ids,
    job_labels,
    line_amplitudes,
    linear_systems,
    load_job,
    load_summary,
    models,
    orbits,
    runout,
    spectral_map,
    spectrum,
    summary,
    sweeps,
    varying_keys,
)

__all__ = [
    "COUNT_COLUMNS",
    "RUN_GROUPS",
    "Job",
    "JobRef",
    "Model",
    "PathLike",
    "Sweep",
    "analysis",
    "analysis_table",
    "campbell",
    "channel",
    "channels",
    "contact_forces",
    "file_attrs",
    "job_attrs",
    "job_id",
    "job_ids",
    "job_labels",
    "line_amplitudes",
    "linear_systems",
    "load_job",
    "load_summary",
    "models",
    "orbits",
    "runout",
    "spectral_map",
    "spectrum",
    "summary",
    "sweeps",
    "varying_keys",
]
__version__ = "0.2.0"
