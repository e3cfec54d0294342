"""rotorsweep: read rotorsweep's HDF5 results as pandas and xarray (:mod:`rotorsweep.results`).

>>> import rotorsweep as rs
>>> df = rs.summary("smoke.h5")                       # one row per job, str text, units in attrs
>>> r = rs.runout("smoke.h5", df.job_id[0])           # xarray: vertical, horizontal over (sensor, time [s])
>>> s = rs.spectrum("smoke.h5", df.job_id[0])         # over (sensor, freq_hz [Hz])
>>> m = rs.spectral_map("smoke.h5", 0)                # over (sensor, speed_hz, freq_hz)

Driving the binary (:mod:`rotorsweep.scene`, :mod:`rotorsweep.runner`):

>>> s = rs.Scene("studies/scenes/reference-roll.toml")
>>> s.set("roll.shell.outer_diameter_mm", 300.0)      # --set semantics, checked by the binary
>>> c = rs.linear(s, speeds="0:60:61")                # what rs.campbell reads from `linear -o`

A sampled study's statistics and Sobol' indices (:mod:`rotorsweep.statistics`):

>>> st = rs.statistics("sens.h5")                     # per output: mean, std, quantiles, 95 % CIs
>>> si = rs.sensitivity("sens.h5")                    # per output and parameter: first_order, total
>>> sa = rs.samples("sens.h5")                        # per job: its sampled inputs and outputs
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
    nip_forces,
    orbits,
    runout,
    spectral_map,
    spectrum,
    summary,
    sweeps,
    varying_keys,
)
from .runner import (
    DEFAULT_TIMEOUT,
    RotorsweepError,
    RotorsweepTimeout,
    RotorsweepWarning,
    find_binary,
    linear,
    modes,
    run,
    simulate,
)
from .calibration import calibration
from .scene import Scene, SceneError, SceneKeyError, SceneValueError
from .statistics import samples, sensitivity, statistics

__all__ = [
    "COUNT_COLUMNS",
    "DEFAULT_TIMEOUT",
    "Job",
    "JobRef",
    "Model",
    "PathLike",
    "RUN_GROUPS",
    "RotorsweepError",
    "RotorsweepTimeout",
    "RotorsweepWarning",
    "Scene",
    "SceneError",
    "SceneKeyError",
    "SceneValueError",
    "Sweep",
    "analysis",
    "analysis_table",
    "calibration",
    "campbell",
    "channel",
    "channels",
    "contact_forces",
    "file_attrs",
    "find_binary",
    "job_attrs",
    "job_id",
    "job_ids",
    "job_labels",
    "line_amplitudes",
    "linear",
    "linear_systems",
    "load_job",
    "load_summary",
    "models",
    "nip_forces",
    "modes",
    "orbits",
    "run",
    "runout",
    "samples",
    "sensitivity",
    "simulate",
    "spectral_map",
    "spectrum",
    "statistics",
    "summary",
    "sweeps",
    "varying_keys",
]
__version__ = "0.2.0"
